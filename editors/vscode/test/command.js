// Prints, as JSON, the command line the extension runs to start the language server,
// found as it finds it (server.js) with no setting, the interpreter given as the first
// argument (or none) and this process's PATH. Exits 1 when none is found.
const { findServer, commandLine } = require("../server");

const found = findServer({ interpreter: process.argv[2] || "" });
if (!found.command) {
  console.error(found.tried.join("\n"));
  process.exit(1);
}
console.log(JSON.stringify(commandLine(found)));
