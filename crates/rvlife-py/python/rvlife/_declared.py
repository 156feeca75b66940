"""The commands' options documented from the library's declaration (``rvlife::api::commands``,
read through the binding): each command function's docstring ends with its options, each with
its unit, default and meaning, the same text the command line's ``--help`` shows (its flags in
Python's spelling)."""

from __future__ import annotations

import inspect
import json
import re
from typing import Any, Callable, Dict, List

from . import _rvlife


def python_text(text: str, names: Dict[str, str]) -> str:
    """``text`` of the command line in Python's spelling: a flag of the command (``names``: its
    options' names on the command line, snake case, to their Python names), ``--torque-nm``, as
    the keyword ``torque_nm``; other text, such as another program's flags, as it is."""

    def keyword(m: "re.Match[str]") -> str:
        name = names.get(m.group(1).replace("-", "_"))
        return m.group(0) if name is None else f"``{name}``"

    return re.sub(r"`?--([a-z][a-z0-9-]*)`?", keyword, text)


def _default(d: Any) -> str:
    if d in ("absent", "off"):
        return ""
    if d == "required":
        return ", required"
    ((_, value),) = d.items()
    return f", default ``{value!r}``"


def options_section(decl: Dict[str, Any]) -> str:
    """The docstring section of the declared command ``decl``: its Python options."""
    names = {o["name"]: o["python_name"] or o["name"] for o in decl["options"]}
    lines: List[str] = [f"Options, as the library declares ``rvlife {decl['name']}``:", ""]
    for o in decl["options"]:
        if "python" not in o["fronts"]:
            continue
        name = names[o["name"]]
        default = o["python_default"] if o["python_default"] is not None else o["default"]
        unit = f" ({o['unit']})" if o["unit"] else ""
        lines.append(f"- ``{name}``{unit}{_default(default)}: {python_text(o['help'], names)}.")
    return "\n".join(lines)


def document(namespace: Dict[str, Callable[..., Any]]) -> None:
    """Appends to each declared command function of ``namespace`` its options' section."""
    for decl in json.loads(_rvlife.commands()):
        fn = namespace.get(decl["python"]) if decl["python"] else None
        if fn is None or not any("python" in o["fronts"] for o in decl["options"]):
            continue
        fn.__doc__ = inspect.cleandoc(fn.__doc__ or "") + "\n\n" + options_section(decl) + "\n"
