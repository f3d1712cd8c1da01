// Tokenizes every mission of missions/ (or the files given) with the extension's
// TextMate grammar, as VS Code does, and checks what a reader relies on: comments,
// strings, reserved words, numbers and units get their scopes, a var's kind, the
// measures force, torque and contact, the log text's {NAME} and the arithmetic
// operators too, and no construct runs past the end of its line. Prints "N passed,
// N failed".
const fs = require("fs");
const path = require("path");
const textmate = require("vscode-textmate");
const oniguruma = require("vscode-oniguruma");

const here = __dirname;
const repo = path.resolve(here, "..", "..", "..");
const RESERVED = ["mission", "library", "import", "let", "behavior", "constraint", "task",
  "start", "state", "final", "parallel", "region", "when", "enter", "during", "exit",
  "enable", "disable", "reset", "attach", "detach", "emit", "log", "var"];
const UNITS = new Set(["m", "cm", "mm", "rad", "deg", "s", "ms", "m/s", "cm/s", "mm/s",
  "rad/s", "deg/s", "m/s^2", "rad/s^2", "deg/s^2", "m/s^3", "rad/s^3", "deg/s^3",
  "N", "kN", "mN", "Nm", "(m/s)/N", "(cm/s)/N", "(mm/s)/N"]);
const KINDS = ["count", "scalar", "length", "angle", "duration", "force", "torque",
  "linear_velocity", "angular_velocity", "position"];

async function grammar() {
  const wasm = fs.readFileSync(require.resolve("vscode-oniguruma/release/onig.wasm"));
  await oniguruma.loadWASM(wasm.buffer.slice(wasm.byteOffset, wasm.byteOffset + wasm.byteLength));
  const registry = new textmate.Registry({
    onigLib: Promise.resolve({
      createOnigScanner: (sources) => new oniguruma.OnigScanner(sources),
      createOnigString: (text) => new oniguruma.OnigString(text),
    }),
    loadGrammar: async () => textmate.parseRawGrammar(
      fs.readFileSync(path.join(here, "..", "syntaxes", "mission.tmLanguage.json"), "utf8"),
      "mission.tmLanguage.json"),
  });
  return registry.loadGrammar("source.mission");
}

// The problems with one line's tokens; [] when it reads as it should.
function problems(line, tokens) {
  const found = [];
  const scopeAt = (index) => {
    const token = tokens.find((t) => t.startIndex <= index && index < t.endIndex);
    return token ? token.scopes.join(" ") : "";
  };
  const code = [];
  let inString = false;
  for (let i = 0; i < line.length; i++) {
    const c = line[i];
    if (inString) {
      if (!scopeAt(i).includes("string.quoted")) found.push(`string not scoped at ${i}`);
      if (c === "\\") i++;
      else if (c === "\"") inString = false;
    } else if (c === "\"") {
      inString = true;
    } else if (c === "#") {
      for (let j = i; j < line.length; j++) {
        if (!scopeAt(j).includes("comment.line")) { found.push(`comment not scoped at ${j}`); break; }
      }
      break;
    } else {
      code.push([i, c]);
    }
  }
  const text = code.map(([, c]) => c).join("");
  const offsets = code.map(([i]) => i);
  for (const match of text.matchAll(/[A-Za-z_][A-Za-z0-9_]*|[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?|[A-Za-z]+(?:\/s(?:\^\d)?)?/g)) {
    const word = match[0];
    const at = offsets[match.index];
    const scope = scopeAt(at);
    const before = text.slice(0, match.index);
    if (RESERVED.includes(word) && !/\.\s*$/.test(before) && !scope.includes("keyword")) {
      found.push(`reserved word '${word}' at ${at} is '${scope}'`);
    }
    if (/^[+-]?[\d.]/.test(word) && !/[A-Za-z_^]$/.test(before) && !scope.includes("constant.numeric")) {
      found.push(`number '${word}' at ${at} is '${scope}'`);
    }
  }
  for (const match of text.matchAll(/(?:\d|\])\s+((?:m|cm|mm|rad|deg)(?:\/s(?:\^[23])?)?|ms|s|k?N|mN|Nm|\((?:m|cm|mm)\/s\)\/N)(?![\w/^])/g)) {
    const at = offsets[match.index + match[0].length - match[1].length];
    if (UNITS.has(match[1]) && !scopeAt(at).includes("keyword.other.unit")) {
      found.push(`unit '${match[1]}' at ${at} is '${scopeAt(at)}'`);
    }
  }
  const expect = (pattern, scope, what) => {
    for (const match of text.matchAll(pattern)) {
      const at = offsets[match.index + match[0].length - match[1].length];
      if (!scopeAt(at).includes(scope)) found.push(`${what} '${match[1]}' at ${at} is '${scopeAt(at)}'`);
    }
  };
  expect(/\bvar\s+\w+\s*:\s*(\w+)/g, "support.type", "kind");
  expect(/\b(force|torque|contact|clearance)\s*\(/g, "support.function", "measure");
  for (const match of line.matchAll(/\blog\s+"(?:[^"\\]|\\.)*?(\{\s*\w+\s*\})/g)) {
    const at = match.index + match[0].length - match[1].length;
    if (!scopeAt(at).includes("constant.other.placeholder")) found.push(`placeholder '${match[1]}' at ${at} is '${scopeAt(at)}'`);
  }
  for (const match of text.matchAll(/[-+*\/]/g)) {
    const at = offsets[match.index];
    if (!/keyword\.operator\.(arithmetic|arrow)|constant\.numeric|keyword\.other\.unit/.test(scopeAt(at))) {
      found.push(`operator '${match[0]}' at ${at} is '${scopeAt(at)}'`);
    }
  }
  return found;
}

async function main() {
  const missions = (folder) => fs.readdirSync(folder).filter((f) => f.endsWith(".mission"))
    .sort().map((f) => path.join(folder, f));
  const files = process.argv.length > 2 ? process.argv.slice(2)
    : [...missions(path.join(repo, "missions")), ...missions(path.join(repo, "tests", "fixtures", "lsp"))];
  const mission = await grammar();
  const base = mission.tokenizeLine("", textmate.INITIAL).ruleStack;
  let passed = 0, failed = 0;
  for (const file of files) {
    let stack = textmate.INITIAL;
    const bad = [];
    fs.readFileSync(file, "utf8").split(/\r?\n/).forEach((line, number) => {
      const result = mission.tokenizeLine(line, stack);
      if (!result.ruleStack.equals(base)) bad.push(`${number + 1}: runs past the line`);
      stack = result.ruleStack;
      for (const problem of problems(line, result.tokens)) bad.push(`${number + 1}: ${problem}`);
    });
    if (bad.length) {
      failed++;
      console.log(`FAIL ${path.relative(repo, file)}\n  ${bad.join("\n  ")}`);
    } else {
      passed++;
      console.log(`ok   ${path.relative(repo, file)}`);
    }
  }
  console.log(`${passed} passed, ${failed} failed`);
  process.exitCode = failed ? 1 : 0;
}

main().catch((error) => { console.error(error); process.exitCode = 2; });
