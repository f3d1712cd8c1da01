// Renders a mission as VS Code shows it: tokens from the extension's TextMate grammar
// (vscode-textmate), VS Code's Dark+ colours, and the language server's diagnostics
// (as `robocop-mission check --format json` prints them) underlined with their message.
//   node test/render.js MISSION DIAGNOSTICS.json > page.html
const fs = require("fs");
const path = require("path");
const textmate = require("vscode-textmate");
const oniguruma = require("vscode-oniguruma");

const COLOURS = [["comment", "#6a9955"], ["constant.other.placeholder", "#569cd6"],
  ["string", "#ce9178"], ["constant.numeric", "#b5cea8"],
  ["keyword.other.unit", "#4ec9b0"], ["keyword.control", "#c586c0"], ["keyword", "#569cd6"],
  ["entity.name.type", "#4ec9b0"], ["entity.name.function", "#dcdcaa"],
  ["entity.name.class", "#4ec9b0"], ["variable.other.constant", "#4fc1ff"],
  ["variable.parameter", "#9cdcfe"], ["variable", "#9cdcfe"], ["constant.language", "#569cd6"],
  ["support.variable", "#9cdcfe"], ["support.type", "#4ec9b0"], ["support.function", "#dcdcaa"],
  ["entity.name", "#dcdcaa"]];
const escape = (text) => text.replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;");

async function main() {
  const [mission, diagnosticsFile] = process.argv.slice(2);
  const wasm = fs.readFileSync(require.resolve("vscode-oniguruma/release/onig.wasm"));
  await oniguruma.loadWASM(wasm.buffer.slice(wasm.byteOffset, wasm.byteOffset + wasm.byteLength));
  const registry = new textmate.Registry({
    onigLib: Promise.resolve({
      createOnigScanner: (s) => new oniguruma.OnigScanner(s),
      createOnigString: (s) => new oniguruma.OnigString(s),
    }),
    loadGrammar: async () => textmate.parseRawGrammar(fs.readFileSync(
      path.join(__dirname, "..", "syntaxes", "mission.tmLanguage.json"), "utf8"), "g.json"),
  });
  const grammar = await registry.loadGrammar("source.mission");
  const diagnostics = JSON.parse(fs.readFileSync(diagnosticsFile, "utf8"))[0].diagnostics;
  let stack = textmate.INITIAL;
  const rows = fs.readFileSync(mission, "utf8").replace(/\n$/, "").split("\n").map((line, index) => {
    const result = grammar.tokenizeLine(line, stack);
    stack = result.ruleStack;
    const marks = diagnostics.filter((d) => d.span && d.span.line === index + 1);
    const html = result.tokens.map((token) => {
      const scopes = token.scopes.join(" ");
      const colour = (COLOURS.find(([scope]) => scopes.includes(scope)) || [0, "#d4d4d4"])[1];
      let text = "";
      for (let i = token.startIndex; i < Math.min(token.endIndex, line.length); i++) {
        const bad = marks.some((d) => d.span.column - 1 <= i && i < d.span.end_column - 1);
        text += bad ? `<u>${escape(line[i])}</u>` : escape(line[i]);
      }
      return `<span style="color:${colour}">${text}</span>`;
    }).join("");
    const notes = marks.map((d) => `<div class="diag">${escape(`${d.severity}[${d.code}]: ${d.message}`)}${
      d.hint ? `<br>hint: ${escape(d.hint)}` : ""}</div>`).join("");
    return `<tr><td class="n">${index + 1}</td><td><pre>${html || " "}</pre>${notes}</td></tr>`;
  });
  process.stdout.write(`<!doctype html><meta charset="utf-8"><style>
body{background:#1e1e1e;margin:0;font:14px/20px monospace;color:#d4d4d4}
.tab{background:#2d2d2d;color:#fff;padding:6px 14px;font-family:sans-serif;font-size:13px}
table{border-collapse:collapse;margin:8px 0} td{vertical-align:top;padding:0}
.n{color:#858585;text-align:right;padding:0 16px 0 12px} pre{margin:0;font:inherit}
u{text-decoration:underline wavy #f14c4c} .diag{background:#3b1d1d;border-left:3px solid #f14c4c;
padding:2px 8px;margin:2px 0;font-family:sans-serif;font-size:12px;color:#f0d0d0}
</style><div class="tab">${escape(path.basename(mission))}</div><table>${rows.join("")}</table>`);
}

main().catch((error) => { console.error(error); process.exitCode = 1; });
