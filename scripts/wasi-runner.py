"""Runs a test binary built for wasm32-wasip1 under Wasmtime (cargo's runner for that target,
set by scripts/wasm-tests): the library's own tests, compiled to WebAssembly, run by their own
harness. The working directory is visible to the tests (as `.`), and so is the system's
temporary directory (for tests that write files). Exits with the harness's code."""

import os
import sys
import tempfile

from wasmtime import Config, Engine, ExitTrap, Linker, Module, Store, WasiConfig


def main() -> int:
    wasm, *args = sys.argv[1:]
    engine = Engine(Config())
    linker = Linker(engine)
    linker.define_wasi()
    tmp = tempfile.gettempdir()
    wasi = WasiConfig()
    wasi.argv = [wasm, *args]
    wasi.env = [*os.environ.items(), ("TMPDIR", tmp)]
    wasi.preopen_dir(os.getcwd(), ".")
    wasi.preopen_dir(tmp, tmp)
    wasi.inherit_stdin()
    wasi.inherit_stdout()
    wasi.inherit_stderr()
    store = Store(engine)
    store.set_wasi(wasi)
    instance = linker.instantiate(store, Module.from_file(engine, wasm))
    try:
        instance.exports(store)["_start"](store)
    except ExitTrap as exit:
        return exit.code
    return 0


if __name__ == "__main__":
    code = main()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
