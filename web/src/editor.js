// The source editor (CodeMirror 6), a bundle of its own (/assets/editor.js) that the
// page loads when a file is first opened, so that the page itself loads fast.
import { EditorView, basicSetup } from "codemirror";
import { EditorState } from "@codemirror/state";
import { linter, lintGutter } from "@codemirror/lint";
import { xml } from "@codemirror/lang-xml";
import { iec } from "./iec.js";

/// Shows `text` (language `lang`: st, il, stl, xml) in `view`, or in a new view
/// under `parent`; `check(text)` gives the diagnostics ({from, to, severity,
/// message}); the cursor goes to `at` if given. Returns the view.
export function show(view, parent, text, lang, check, at) {
  const state = EditorState.create({
    doc: text,
    extensions: [
      basicSetup,
      lang === "xml" ? xml() : iec,
      linter(async (v) => check(v.state.doc.toString(), v.state.doc.length), { delay: 500 }),
      lintGutter(),
      EditorView.contentAttributes.of({ "aria-label": "Source editor" }),
    ],
  });
  if (view) view.setState(state);
  else view = new EditorView({ parent, state });
  if (at !== undefined) view.dispatch({ selection: { anchor: at }, effects: EditorView.scrollIntoView(at, { y: "start" }) });
  return view;
}
