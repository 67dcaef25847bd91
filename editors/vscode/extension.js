// The Snell extension's client: starts `snell lsp` (settings snell.server.*)
// for .scn documents. Everything else (diagnostics, hover, completion,
// definitions, outline) is the server's; the grammar is syntaxes/.
const vscode = require("vscode");
const { LanguageClient } = require("vscode-languageclient/node");

let client;

function serverOptions() {
  const cfg = vscode.workspace.getConfiguration("snell.server");
  const args = ["lsp"];
  for (const dir of cfg.get("includeDirs", [])) args.push("-I", dir);
  const steps = cfg.get("maxSteps");
  if (Number.isInteger(steps)) args.push("--max-steps", String(steps));
  return { command: cfg.get("path", "snell") || "snell", args };
}

async function activate(context) {
  client = new LanguageClient("snell", "Snell", serverOptions(), {
    documentSelector: [
      { scheme: "file", language: "snell" },
      { scheme: "untitled", language: "snell" },
    ],
    // An imported file changed outside the editor: the server analyses again.
    synchronize: { fileEvents: vscode.workspace.createFileSystemWatcher("**/*.scn") },
  });
  context.subscriptions.push(
    vscode.workspace.onDidChangeConfiguration(async (e) => {
      if (!e.affectsConfiguration("snell.server") || !client) return;
      await client.stop();
      client = new LanguageClient("snell", "Snell", serverOptions(), client.clientOptions);
      await client.start();
    })
  );
  await client.start();
}

async function deactivate() {
  if (client) await client.stop();
}

module.exports = { activate, deactivate };
