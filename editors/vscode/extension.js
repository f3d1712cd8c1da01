// Starts the robocop-mission language server for .mission files and connects VS Code to
// it over stdio. The server is looked for in the workspace's Python environment (see
// server.js); when it cannot be found or started, a message says what was tried and
// how to install it. A change of the robocopMission settings or of the Python
// extension's interpreter starts it again.
const vscode = require("vscode");
const { LanguageClient, TransportKind } = require("vscode-languageclient/node");
const { findServer } = require("./server");

const NAME = "RoboCoP missions";
let client;

// The Python extension's interpreter for the workspace, or "" (no extension, none set).
async function pythonInterpreter() {
  const extension = vscode.extensions.getExtension("ms-python.python");
  if (!extension) return "";
  try {
    const api = extension.isActive ? extension.exports : await extension.activate();
    const resource = vscode.workspace.workspaceFolders?.[0]?.uri;
    if (api.environments) {
      const active = api.environments.getActiveEnvironmentPath(resource);
      const resolved = await api.environments.resolveEnvironment(active);
      return resolved?.executable?.uri?.fsPath || "";
    }
    return api.settings?.getExecutionDetails(resource)?.execCommand?.[0] || "";
  } catch {
    return "";
  }
}

async function notFound(found) {
  const lines = [`${NAME}: the language server was not found.`,
    `Tried: ${found.tried.join("; ")}.`];
  lines.push(found.problem
    ? `Fix the setting: ${found.problem}.`
    : `Install it in the workspace's Python environment: ${found.install} ` +
      "(from a clone of the repository: pip install -e .), or set robocopMission.serverPath.");
  const actions = found.install ? ["Copy the install command", "Open Settings"] : ["Open Settings"];
  const chosen = await vscode.window.showErrorMessage(lines.join(" "), ...actions);
  if (chosen === "Open Settings") {
    vscode.commands.executeCommand("workbench.action.openSettings", "robocopMission");
  } else if (chosen) {
    vscode.env.clipboard.writeText(found.install);
  }
}

async function start(context) {
  const settings = vscode.workspace.getConfiguration("robocopMission");
  const found = findServer({
    serverPath: settings.get("serverPath", ""),
    pythonPath: settings.get("pythonPath", ""),
    interpreter: await pythonInterpreter(),
    workspace: vscode.workspace.workspaceFolders?.[0]?.uri.fsPath ?? "",
  });
  if (!found.command) {
    await notFound(found);
    return;
  }
  const server = { command: found.command, args: found.args, transport: TransportKind.stdio };
  client = new LanguageClient("robocopMission", NAME, { run: server, debug: server }, {
    documentSelector: [{ scheme: "file", language: "mission" }],
    synchronize: {
      fileEvents: vscode.workspace.createFileSystemWatcher("**/*.{mission,yaml,urdf}"),
    },
  });
  context.subscriptions.push(client);
  try {
    await client.start();
  } catch (error) {
    vscode.window.showErrorMessage(`${NAME}: ${[found.command, ...found.args].join(" ")} ` +
      `did not start (${error.message || error}). Check that it runs in a terminal, or set ` +
      "robocopMission.serverPath or robocopMission.pythonPath.");
  }
}

async function restart(context) {
  if (client) {
    const stopping = client;
    client = undefined;
    await stopping.stop().catch(() => undefined);
  }
  await start(context);
}

async function activate(context) {
  context.subscriptions.push(vscode.workspace.onDidChangeConfiguration((event) => {
    if (event.affectsConfiguration("robocopMission")) restart(context);
  }));
  await start(context);
  const python = vscode.extensions.getExtension("ms-python.python");
  const api = python?.isActive ? python.exports : undefined;
  if (api?.environments?.onDidChangeActiveEnvironmentPath) {
    context.subscriptions.push(api.environments.onDidChangeActiveEnvironmentPath(
      () => restart(context)));
  }
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
