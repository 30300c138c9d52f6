// Tokenizes ST and IL lines with the extension's grammars, as VS Code does
// (vscode-textmate with the Oniguruma engine), and checks the scope of each token
// named. Run by tests/vscode.rs: `node test/dist/grammar-test.js`; exit status 1 and
// the differences on standard error when a check fails.
import { readFileSync } from "node:fs";
import { join } from "node:path";
import * as oniguruma from "vscode-oniguruma";
import * as textmate from "vscode-textmate";

const root = join(__dirname, "..", "..");
const wasm = readFileSync(join(__dirname, "onig.wasm")).buffer;

const files = {
  "source.iec-st": "syntaxes/st.tmLanguage.json",
  "source.iec-il": "syntaxes/il.tmLanguage.json",
};

async function main() {
  await oniguruma.loadWASM(wasm);
  const registry = new textmate.Registry({
    onigLib: Promise.resolve({
      createOnigScanner: (sources) => new oniguruma.OnigScanner(sources),
      createOnigString: (s) => new oniguruma.OnigString(s),
    }),
    loadGrammar: async (scope) => {
      const file = files[scope];
      if (!file) return null;
      const text = readFileSync(join(root, file), "utf8");
      return textmate.parseRawGrammar(text, file);
    },
  });
  // [grammar, lines, [token text, scope it must have]...]
  const cases = JSON.parse(readFileSync(join(root, "test", "cases.json"), "utf8"));
  let checks = 0;
  const failures = [];
  for (const c of cases) {
    const grammar = await registry.loadGrammar(c.grammar);
    let state = textmate.INITIAL;
    const tokens = [];
    for (const line of c.lines) {
      const r = grammar.tokenizeLine(line, state);
      for (const t of r.tokens) {
        tokens.push({ text: line.slice(t.startIndex, t.endIndex), scopes: t.scopes });
      }
      state = r.ruleStack;
    }
    for (const [text, scope] of c.expect) {
      checks++;
      const tok = tokens.find((t) => t.text === text);
      if (!tok) {
        failures.push(`${c.name}: no token \`${text}\``);
      } else if (scope === null ? tok.scopes.length > 1 : !tok.scopes.includes(scope)) {
        failures.push(
          `${c.name}: \`${text}\` has ${tok.scopes.join(" ")}, want ${scope === null ? "no scope" : scope}`,
        );
      }
    }
  }
  if (failures.length > 0) {
    console.error(failures.join("\n"));
    process.exit(1);
  }
  console.log(`${checks} checks in ${cases.length} cases passed`);
}

main().catch((e) => {
  console.error(e);
  process.exit(1);
});
