// Starts `robocop-mission lsp` for .mission files and connects VS Code to it over stdio.
const vscode = require("vscode");
const { LanguageClient, TransportKind } = require("vscode-languageclient/node");

let client;

function activate(context) {
  const [command, ...args] = vscode.workspace
    .getConfiguration("robocopMission")
    .get("serverCommand", ["robocop-mission", "lsp"]);
  const server = { command, args, transport: TransportKind.stdio };
  client = new LanguageClient(
    "robocopMission",
    "RoboCoP missions",
    { run: server, debug: server },
    {
      documentSelector: [{ scheme: "file", language: "mission" }],
      synchronize: {
        fileEvents: vscode.workspace.createFileSystemWatcher("**/*.{mission,yaml,urdf}"),
      },
    }
  );
  context.subscriptions.push(client);
  return client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
