// A minimal client: start `gaitgram lsp` over stdio for .gg documents.
const vscode = require("vscode");
const { LanguageClient } = require("vscode-languageclient/node");

let client;

function activate(context) {
  const [command, ...args] = vscode.workspace.getConfiguration("gaitgram").get("serverCommand");
  client = new LanguageClient(
    "gaitgram",
    "gaitgram",
    { command, args },
    { documentSelector: [{ language: "gaitgram" }] }
  );
  context.subscriptions.push({ dispose: () => client.stop() });
  return client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
