// Tokenizes files with the VS Code extension's TextMate grammar, exactly as VS Code does
// (vscode-textmate + vscode-oniguruma), and prints JSON: for each file, the text that got no
// scope beyond the root. Usage: node tokenize.js GRAMMAR.tmLanguage.json FILE...
// NODE_PATH must hold vscode-textmate and vscode-oniguruma.
const fs = require("fs");
const path = require("path");
const textmate = require("vscode-textmate");
const oniguruma = require("vscode-oniguruma");

async function main() {
  const [grammarPath, ...files] = process.argv.slice(2);
  const wasm = fs.readFileSync(path.join(path.dirname(require.resolve("vscode-oniguruma")), "onig.wasm"));
  await oniguruma.loadWASM(wasm.buffer);
  const registry = new textmate.Registry({
    onigLib: Promise.resolve({
      createOnigScanner: (patterns) => new oniguruma.OnigScanner(patterns),
      createOnigString: (text) => new oniguruma.OnigString(text),
    }),
    loadGrammar: async () => textmate.parseRawGrammar(fs.readFileSync(grammarPath, "utf8"), grammarPath),
  });
  const grammar = await registry.loadGrammar("source.gaitgram");
  const report = {};
  for (const file of files) {
    let state = textmate.INITIAL;
    const unscoped = [];
    const scopes = new Set();
    fs.readFileSync(file, "utf8").split(/\r?\n/).forEach((line, number) => {
      const result = grammar.tokenizeLine(line, state);
      for (const token of result.tokens) {
        const text = line.slice(token.startIndex, token.endIndex);
        token.scopes.forEach((s) => scopes.add(s));
        if (token.scopes.length === 1 && text.trim() !== "") unscoped.push([number + 1, text]);
      }
      state = result.ruleStack;
    });
    report[file] = { unscoped, scopes: [...scopes].sort() };
  }
  console.log(JSON.stringify(report));
}

main().catch((error) => {
  console.error(error);
  process.exit(1);
});
