// Builds the workbench page into dist/: app.js, editor.js and app.css (minified, every npm
// package bundled), index.html, and LICENSES.txt (the licences of the bundled
// packages). plcc embeds dist/ (src/serve/project.rs): the Rust build needs no node.
import * as esbuild from "esbuild";
import { copyFileSync, mkdirSync, readFileSync, writeFileSync, existsSync, readdirSync } from "node:fs";
import { dirname, join } from "node:path";

const out = "dist";
mkdirSync(out, { recursive: true });
// Two bundles: the page (app.js, app.css) and the source editor (editor.js), which
// the page imports when a file is first opened.
const result = await esbuild.build({
  entryPoints: { app: "src/main.js", editor: "src/editor.js" },
  bundle: true,
  minify: true,
  format: "esm",
  target: ["es2020"],
  outdir: out,
  external: ["/assets/*"],
  metafile: true,
  legalComments: "none",
  logLevel: "warning",
});
copyFileSync("src/index.html", join(out, "index.html"));

// The packages whose code is in the bundle, with their licence texts.
const packages = new Map();
for (const input of Object.keys(result.metafile.inputs)) {
  const m = input.match(/node_modules\/((?:@[^/]+\/)?[^/]+)\//);
  if (m) packages.set(m[1], join("node_modules", m[1]));
}
let text =
  "The workbench page of plcc (web/dist/app.js, editor.js, app.css) bundles these npm packages.\n" +
  "Their licences follow.\n";
for (const [name, dir] of [...packages].sort()) {
  const pkg = JSON.parse(readFileSync(join(dir, "package.json"), "utf8"));
  const file = readdirSync(dir).find((f) => /^(licen[sc]e|copying)/i.test(f));
  text += `\n${"=".repeat(78)}\n${name} ${pkg.version}: ${pkg.license}\n${"=".repeat(78)}\n\n`;
  text += file ? readFileSync(join(dir, file), "utf8").trim() + "\n" : `(licence ${pkg.license}, no licence file in the package)\n`;
}
writeFileSync(join(out, "LICENSES.txt"), text);

// What dist/ was built from: a FNV-1a 64 of every source file, which a test of the
// Rust build compares with the sources in the repository (a changed source with an
// old bundle fails it).
const fnv = (bytes) => {
  let h = 0xcbf29ce484222325n;
  for (const b of bytes) h = BigInt.asUintN(64, (h ^ BigInt(b)) * 0x100000001b3n);
  return h.toString(16).padStart(16, "0");
};
const sources = ["build.mjs", "package.json", "package-lock.json", ...readdirSync("src").sort().map((f) => `src/${f}`)];
writeFileSync(
  join(out, "SOURCES.txt"),
  "# FNV-1a 64 of the files web/dist/ was built from (src/serve/project.rs checks them)\n" +
    sources.map((f) => `${fnv(readFileSync(f))}  ${f}\n`).join("")
);
console.log(`dist/: ${packages.size} packages bundled`);
