// Builds the extension into dist/extension.js (vscode-languageclient bundled; the
// `vscode` module is VS Code's) with dist/LICENSES.txt, and the grammar test into
// test/dist/ (vscode-textmate and vscode-oniguruma bundled, onig.wasm beside it).
// Both outputs are committed: plcc's tests run the grammar test with node alone.
import * as esbuild from "esbuild";
import { copyFileSync, mkdirSync, readFileSync, writeFileSync, existsSync, readdirSync } from "node:fs";
import { join } from "node:path";

const common = {
  bundle: true,
  platform: "node",
  format: "cjs",
  target: ["node18"],
  metafile: true,
  legalComments: "none",
  logLevel: "warning",
};
mkdirSync("dist", { recursive: true });
const ext = await esbuild.build({
  ...common,
  entryPoints: ["src/extension.js"],
  outfile: "dist/extension.js",
  external: ["vscode"],
  minify: true,
});
mkdirSync("test/dist", { recursive: true });
await esbuild.build({
  ...common,
  entryPoints: ["test/grammar-test.mjs"],
  outfile: "test/dist/grammar-test.js",
});
copyFileSync("node_modules/vscode-oniguruma/release/onig.wasm", "test/dist/onig.wasm");

// The licences of the packages bundled into the extension.
const packages = new Map();
for (const input of Object.keys(ext.metafile.inputs)) {
  const m = input.match(/node_modules\/((?:@[^/]+\/)?[^/]+)\//);
  if (m) packages.set(m[1], join("node_modules", m[1]));
}
let licences = "";
for (const [name, dir] of [...packages].sort()) {
  const version = JSON.parse(readFileSync(join(dir, "package.json"), "utf8")).version;
  const file = readdirSync(dir).find((f) => /^licen[cs]e/i.test(f));
  licences += `${name} ${version}\n\n${file && existsSync(join(dir, file)) ? readFileSync(join(dir, file), "utf8") : "(no licence file)"}\n\n`;
}
writeFileSync("dist/LICENSES.txt", licences);
