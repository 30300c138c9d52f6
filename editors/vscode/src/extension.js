// The client of plcc's language server: starts `plcc lsp` (the binary named by the
// `plcc.path` setting) for ST, IL, PLC-UD STL and PLCopen XML files. Everything
// else (diagnostics, hover, definition, references, rename, completion, outline,
// formatting, semantic tokens) is the server's; see docs/editors.md.
const vscode = require("vscode");
const { LanguageClient, TransportKind } = require("vscode-languageclient/node");

/** The client, while the extension is active. */
let client;

/** The documents the server is for. */
const documentSelector = [
  { scheme: "file", language: "iec-st" },
  { scheme: "file", language: "iec-il" },
  { scheme: "file", language: "plcud-stl" },
  { scheme: "file", pattern: "**/*.xml" },
];

function activate(context) {
  const command = vscode.workspace.getConfiguration("plcc").get("path", "plcc");
  const server = { command, args: ["lsp"], transport: TransportKind.stdio };
  client = new LanguageClient(
    "plcc",
    "plcc",
    { run: server, debug: server },
    { documentSelector, outputChannelName: "plcc" },
  );
  context.subscriptions.push(client);
  return client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate, documentSelector };
