// Runs a test binary built for wasm32-wasip1 under Node's WASI (cargo's runner for that
// target, set by scripts/wasm-tests): the library's own tests, compiled to WebAssembly,
// run by their own harness. The working directory is visible to the tests (as `.`), and so
// is the system's temporary directory (for tests that write files).
import fs from 'node:fs';
import os from 'node:os';
import { WASI } from 'node:wasi';

const [wasm, ...args] = process.argv.slice(2);
const tmp = os.tmpdir();
const wasi = new WASI({
  version: 'preview1',
  args: [wasm, ...args],
  env: { ...process.env, TMPDIR: tmp },
  preopens: { '.': process.cwd(), [tmp]: tmp },
  returnOnExit: true,
});
const module = await WebAssembly.compile(fs.readFileSync(wasm));
const instance = await WebAssembly.instantiate(module, wasi.getImportObject());
// Exit at once with the harness's code (Node 20 can crash tearing a large WASI instance down).
process.exit(wasi.start(instance));
