// How the extension finds the language server (server.js), with programs made for the
// test in a temporary folder, and the command line it builds.
const test = require("node:test");
const assert = require("node:assert");
const fs = require("fs");
const os = require("os");
const path = require("path");
const { findServer, commandLine } = require("../server");

const folder = fs.mkdtempSync(path.join(os.tmpdir(), "robocop-mission-"));
const program = path.join(folder, "robocop-mission");
const python = path.join(folder, "python");
for (const file of [program, python]) fs.writeFileSync(file, "#!/bin/sh\n", { mode: 0o755 });
const empty = { PATH: path.join(folder, "missing") };
const withProgram = { PATH: folder };
const installed = () => true;
const missing = () => false;

test.after(() => fs.rmSync(folder, { recursive: true, force: true }));

test("the setting serverPath comes first", () => {
  const found = findServer({ serverPath: program, pythonPath: python, interpreter: python,
    env: empty, probe: installed });
  assert.deepStrictEqual(commandLine(found), [program, "lsp", "--stdio"]);
});

test("then the setting pythonPath", () => {
  const found = findServer({ pythonPath: python, interpreter: "/other/python", env: empty });
  assert.deepStrictEqual(commandLine(found), [python, "-m", "robocop_dsl", "lsp", "--stdio"]);
});

test("then the Python extension's interpreter when it has the server", () => {
  const found = findServer({ interpreter: python, env: withProgram, probe: installed });
  assert.deepStrictEqual(commandLine(found), [python, "-m", "robocop_dsl", "lsp", "--stdio"]);
});

test("then robocop-mission on PATH", () => {
  const found = findServer({ interpreter: python, env: withProgram, probe: missing });
  assert.deepStrictEqual(commandLine(found), [program, "lsp", "--stdio"]);
  assert.match(found.tried.join("\n"), /robocop_dsl is not installed in it/);
});

test("nothing found: what was tried and the install command", () => {
  const found = findServer({ interpreter: python, env: empty, probe: missing });
  assert.strictEqual(found.command, null);
  assert.deepStrictEqual(found.tried, [
    "the setting robocopMission.serverPath (not set)",
    "the setting robocopMission.pythonPath (not set)",
    `the Python interpreter ${python} (robocop_dsl is not installed in it)`,
    "robocop-mission on PATH (not found)",
  ]);
  assert.strictEqual(found.install, `${python} -m pip install robocop-mission`);
});

test("a setting naming a missing program is reported, not passed over", () => {
  const found = findServer({ serverPath: path.join(folder, "nope"), env: withProgram });
  assert.strictEqual(found.command, null);
  assert.match(found.problem, /robocopMission.serverPath names .*nope, which is not a program/);
});

test("a setting may name a program on PATH, from the home folder or the workspace", () => {
  assert.deepStrictEqual(commandLine(findServer({ serverPath: "robocop-mission", env: withProgram })),
    [program, "lsp", "--stdio"]);
  assert.deepStrictEqual(commandLine(findServer({ pythonPath: "python", env: withProgram })),
    [python, "-m", "robocop_dsl", "lsp", "--stdio"]);
  const inWorkspace = findServer({ serverPath: "${workspaceFolder}/robocop-mission",
    workspace: folder, env: empty });
  assert.strictEqual(inWorkspace.command, program);
  const home = process.env.HOME;
  process.env.HOME = folder;
  try {
    assert.strictEqual(findServer({ serverPath: "~/robocop-mission", env: empty }).command,
      program);
  } finally {
    process.env.HOME = home;
  }
  assert.strictEqual(findServer({ serverPath: "./robocop-mission", workspace: folder,
    env: empty }).command, program);
  assert.match(findServer({ serverPath: "${workspaceFolder}/robocop-mission", env: empty }).problem,
    /which is not a program \(no folder is open\)/);
  const absent = findServer({ serverPath: "robocop-mission", env: empty });
  assert.match(absent.problem, /robocopMission.serverPath names robocop-mission, which is not a program/);
});

// vscode-languageclient's code, once `npm ci` has installed it.
function clientCode() {
  try {
    return require.resolve("vscode-languageclient/lib/node/main.js");
  } catch {
    return null;
  }
}

test("the client appends --stdio for a stdio executable, as commandLine does",
  { skip: clientCode() ? false : "vscode-languageclient is not installed (npm ci)" }, () => {
  const client = fs.readFileSync(clientCode(), "utf8");
  const executable = client.slice(client.indexOf("Executable.is(json) && json.command"));
  assert.match(executable.slice(0, 600), /transport === TransportKind\.stdio\) \{\s*args\.push\('--stdio'\)/);
});
