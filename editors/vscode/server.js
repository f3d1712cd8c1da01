// Where the language server is and the command line that starts it, without VS Code:
// extension.js gives the settings and the Python extension's interpreter; the tests
// give their own.
//
// In order: the setting robocopMission.serverPath (the robocop-mission program), the
// setting robocopMission.pythonPath (an interpreter that has robocop_dsl), the Python
// extension's interpreter for the workspace when robocop_dsl is installed in it, then
// robocop-mission on PATH. A setting may give a program's name (looked up on PATH), a
// path from the home folder (~/) or from the workspace (${workspaceFolder}, or a
// relative path). When none fits, `tried` says what was looked at and
// `install` the command that installs the server.
const fs = require("fs");
const os = require("os");
const path = require("path");
const { spawnSync } = require("child_process");

const PACKAGE = "robocop-mission";
const MODULE = ["-m", "robocop_dsl", "lsp"];
const PROGRAM = ["lsp"];
// vscode-languageclient appends this for TransportKind.stdio (an Executable server).
const STDIO = "--stdio";

function executable(file) {
  try {
    fs.accessSync(file, fs.constants.X_OK);
    return fs.statSync(file).isFile();
  } catch {
    return false;
  }
}

// The full path of `name` in the folders of PATH, or null.
function onPath(name, env = process.env, platform = process.platform) {
  const folders = (env.PATH || env.Path || "").split(path.delimiter).filter(Boolean);
  const endings = platform === "win32" ? ["", ...(env.PATHEXT || ".EXE;.CMD;.BAT").split(";")] : [""];
  for (const folder of folders) {
    for (const ending of endings) {
      const file = path.join(folder, name + ending.toLowerCase());
      if (executable(file)) return file;
    }
  }
  return null;
}

// Whether `python` runs and imports robocop_dsl.
function hasServer(python) {
  const run = spawnSync(python, ["-c", "import robocop_dsl.lsp"], { timeout: 20000 });
  return run.status === 0;
}

function quoted(file) {
  return /\s/.test(file) ? `"${file}"` : file;
}

// The program a setting names: `~/` is the home folder, `${workspaceFolder}` the
// workspace's folder, and a bare name (`python3`, `robocop-mission`) is looked up on
// PATH; null when that names no program.
function resolved(setting, workspace, env, platform) {
  let file = setting.replace(/^~(?=$|[\\/])/, os.homedir());
  if (workspace) file = file.split("${workspaceFolder}").join(workspace);
  if (!/[\\/]/.test(file)) return onPath(file, env, platform);
  if (workspace && !path.isAbsolute(file)) file = path.join(workspace, file);
  return executable(file) ? file : null;
}

// The server to start: { command, args, tried } (command null when none was found, with
// `install`, the command to run, and `problem` when a setting names a missing file).
function findServer({ serverPath = "", pythonPath = "", interpreter = "", workspace = "",
  env = process.env, platform = process.platform, probe = hasServer } = {}) {
  const tried = [];
  for (const [setting, given, args] of [["serverPath", serverPath, PROGRAM],
    ["pythonPath", pythonPath, MODULE]]) {
    if (!given) {
      tried.push(`the setting robocopMission.${setting} (not set)`);
      continue;
    }
    const file = resolved(given, workspace, env, platform);
    if (!file) {
      tried.push(`the setting robocopMission.${setting}: ${given} (no such program)`);
      const folder = !workspace && given.includes("${workspaceFolder}") ? " (no folder is open)" : "";
      return { command: null, args: [], tried, problem: `robocopMission.${setting} names ${given}, which is not a program${folder}` };
    }
    return { command: file, args, tried };
  }
  if (!interpreter) {
    tried.push("the Python extension's interpreter (no Python extension or no interpreter selected)");
  } else if (probe(interpreter)) {
    return { command: interpreter, args: MODULE, tried };
  } else {
    tried.push(`the Python interpreter ${interpreter} (robocop_dsl is not installed in it)`);
  }
  const program = onPath(PACKAGE, env, platform);
  if (program) return { command: program, args: PROGRAM, tried };
  tried.push(`${PACKAGE} on PATH (not found)`);
  const python = interpreter ? quoted(interpreter) : "python";
  return { command: null, args: [], tried, install: `${python} -m pip install ${PACKAGE}` };
}

// The command line the language client runs for a server found by findServer.
function commandLine(found) {
  return [found.command, ...found.args, STDIO];
}

module.exports = { findServer, commandLine, onPath, hasServer, STDIO };
