"""The Python functions against the library's declaration of the commands
(``rvlife::api::commands::COMMANDS``, read through the binding): every declared command is a
function, with every option the declaration gives Python as a keyword of the declared default,
and no keyword the declaration does not name."""

import inspect
import json

import pytest

import rvlife
from rvlife import _rvlife

#: What a function takes besides the command's options: the config (or the configs of a sweep
#: and the base of a search), the progress callback, the Dask client.
PLUMBING = {"config", "progress", "client", "base", "configs_or_samples"}

#: The package's functions that are no command of the command line, and why.
NOT_COMMANDS = {
    "accuracy_life": "the study's accuracy life alone (rvlife run's summary)",
    "calibrate_structure": "rvlife calibrate --measured CURVE or --catalogue-stiffness-nm-per-arcmin",
    "presets": "rvlife example --list",
    "quantities": "the table of stage quantities",
    "grid": "builds the designs of a sweep",
    "tqdm_progress": "a progress bar",
}

COMMANDS = json.loads(_rvlife.commands())


def expected_default(d):
    """The Python default of a declared default."""
    if d == "absent":
        return None
    if d == "required":
        return inspect.Parameter.empty
    if d == "off":
        return False
    ((kind, value),) = d.items()
    return value


@pytest.mark.parametrize("decl", [c for c in COMMANDS if c["python"]], ids=lambda c: c["name"])
def test_every_declared_option_is_a_keyword_with_its_default(decl):
    fn = getattr(rvlife, decl["python"])
    params = {n: p for n, p in inspect.signature(fn).parameters.items() if n not in PLUMBING}
    options = {}
    for o in decl["options"]:
        if "python" in o["fronts"]:
            name = o["python_name"] or o["name"]
            options[name] = o["python_default"] if o["python_default"] is not None else o["default"]
    assert set(params) == set(options), f"rvlife.{decl['python']}: keywords and declared options differ"
    for name, d in options.items():
        got = params[name].default
        if got == ():
            got = None  # an empty sequence: none given
        assert got == expected_default(d), f"rvlife.{decl['python']}({name}=...): default"


def test_every_function_is_a_declared_command_or_says_why_not():
    declared = {c["python"] for c in COMMANDS if c["python"]}
    functions = {
        n
        for n in rvlife.__all__
        if n[0].islower() and callable(getattr(rvlife, n)) and not inspect.isclass(getattr(rvlife, n))
    }
    assert functions - declared - set(NOT_COMMANDS) == set()
    assert declared <= functions


def _stubs():
    """The native module's stub (``_rvlife.pyi``): its functions' parameters with their
    defaults (as source text), and its classes."""
    import ast
    from pathlib import Path

    tree = ast.parse((Path(rvlife.__file__).parent / "_rvlife.pyi").read_text())
    functions = {}
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            a = node.args
            params = a.args + a.kwonlyargs
            defaults = [None] * (len(a.args) - len(a.defaults)) + list(a.defaults) + list(a.kw_defaults)
            functions[node.name] = [(p.arg, None if d is None else ast.unparse(d)) for p, d in zip(params, defaults)]
    classes = {n.name for n in tree.body if isinstance(n, ast.ClassDef)}
    return functions, classes


def test_the_native_stub_is_the_native_module():
    """The generated stub (pyo3-stub-gen, ``tests/stub.rs``) against the loaded native
    module's signatures (PyO3's ``__text_signature__``): the same functions, parameters in the
    same order, the same defaults."""
    functions, classes = _stubs()
    native = {n for n in dir(_rvlife) if not n.startswith("_")}
    assert native - set(functions) - classes == set(), "native functions without a stub"
    assert set(functions) - native == set(), "stubs of no native function"
    for name, params in functions.items():
        sig = inspect.signature(getattr(_rvlife, name))
        got = [(p.name, None if p.default is inspect.Parameter.empty else repr(p.default)) for p in sig.parameters.values()]
        assert [p for p, _ in got] == [p for p, _ in params], f"_rvlife.{name}: parameters"
        for (p, d), (_, stub) in zip(got, params):
            if d is None:
                continue
            assert stub is not None, f"_rvlife.{name}({p}=...): the stub has no default"
            # `...`: a default PyO3 cannot write as Python (a Rust constant).
            if d != "Ellipsis":
                assert eval(stub) == eval(d), f"_rvlife.{name}({p}=...): default {stub} against {d}"


@pytest.mark.parametrize("decl", [c for c in COMMANDS if c["python"]], ids=lambda c: c["name"])
def test_every_declared_option_is_documented_from_the_declaration(decl):
    """Each command function's docstring carries each of its Python options' declared help (the
    command line's ``--help`` text, its flags in Python's spelling) under the option's name."""
    from rvlife._declared import python_text

    doc = getattr(rvlife, decl["python"]).__doc__ or ""
    names = {o["name"]: o["python_name"] or o["name"] for o in decl["options"]}
    for o in decl["options"]:
        if "python" not in o["fronts"]:
            continue
        name = o["python_name"] or o["name"]
        assert o["help"], f"rvlife.{decl['python']}({name}=...): no help declared"
        assert f"- ``{name}``" in doc and python_text(o["help"], names) in doc, (
            f"rvlife.{decl['python']}({name}=...): its declared help is not in the docstring"
        )
