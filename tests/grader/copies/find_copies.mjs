// The class grader's copy finder (tests/grader/similarity.py runs it): one task's files compared
// pair by pair by Dolos, whose tokens are the syntax tree's node types (tree-sitter), so renamed
// names, changed layout, moved comments and reordered functions do not hide a copy.
//
// Reads one JSON request on standard input:
//   {"language": "c" | "cpp", "kgram": K, "window": W, "sharedBy": N or null, "floor": F,
//    "template": the stub's text, "files": [{"name": ..., "text": ...}, ...]}
// and writes {"pairs": [...]}: each pair of which at least the share F (0 to 1) of one file's
// fingerprints is found in the other, with its covered and own fingerprints, its longest run
// and its fragments as [first row, last row] in each file (rows from 0). Fingerprints of the
// template, and those found in more than `sharedBy` files, count for no pair.
import { CodeTokenizer, CustomTreeSitterLanguage, File, FingerprintIndex } from "@dodona/dolos-lib";
import { readFileSync } from "node:fs";

const request = JSON.parse(readFileSync(0, "utf8"));
const grammar = { c: "tree-sitter-c", cpp: "tree-sitter-cpp" }[request.language];
if (!grammar) throw new Error(`unknown language ${request.language}`);
const language = new CustomTreeSitterLanguage(request.language, [], grammar);
await language.loadLanguageModule();
const tokenizer = new CodeTokenizer(language, { includeComments: false });
const index = new FingerprintIndex(request.kgram, request.window, false, request.sharedBy ?? undefined);
index.addFiles(request.files.map(file => tokenizer.tokenizeFile(new File(file.name, file.text))));
if (request.template) index.addIgnoredFile(tokenizer.tokenizeFile(new File("template", request.template)));

// A file's own fingerprints: those neither in the template nor in too many files.
const own = entry => Math.max(0, entry.kgrams.length - entry.ignored.size);
const share = (covered, entry) => (own(entry) > 0 ? covered / own(entry) : 0);
const pairs = index.allPairs().filter(pair =>
  Math.max(share(pair.leftCovered, pair.leftEntry), share(pair.rightCovered, pair.rightEntry)) >= request.floor,
).map(pair => ({
  first: pair.leftFile.path,
  second: pair.rightFile.path,
  firstCovered: pair.leftCovered,
  secondCovered: pair.rightCovered,
  firstOwn: own(pair.leftEntry),
  secondOwn: own(pair.rightEntry),
  longest: pair.longest,
  fragments: pair.buildFragments().map(fragment => [
    [fragment.leftSelection.startRow, fragment.leftSelection.endRow],
    [fragment.rightSelection.startRow, fragment.rightSelection.endRow],
    fragment.pairs.length,
  ]),
}));
process.stdout.write(JSON.stringify({ pairs }));
