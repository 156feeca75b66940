"""Configs as values: built from a file, TOML text, a (partial) dict or a preset, edited by
dotted key, compared, and turned back into a dict or TOML; validated on construction exactly
as ``rvlife`` validates a file."""

from __future__ import annotations

import functools
import json
import os
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Tuple, Union

from . import _rvlife
from ._results import _plain

PathLike = Union[str, "os.PathLike[str]"]

#: The command line's default work budget, minutes of estimated computing on 2 cores.
DEFAULT_WORK_BUDGET_MIN = 10.0


def _json(v: Any) -> str:
    """``v`` as JSON, numpy numbers as Python's."""

    def plain(x: Any) -> Any:
        if hasattr(x, "item") and callable(x.item) and getattr(x, "shape", None) == ():
            return x.item()
        if hasattr(x, "tolist") and callable(x.tolist):
            return x.tolist()
        raise TypeError(f"a value of type {type(x).__name__} cannot go into a config")

    return json.dumps(v, default=plain, allow_nan=False)


class Config:
    """A reducer, its tolerances and its duty: the TOML config of the command line, as a value.

    Build one with :meth:`from_file`, :meth:`from_toml`, :meth:`from_dict` (a partial dict over
    a base, the built-in example by default) or :func:`rvlife.example`; derive others with
    :meth:`replace` (dotted keys). Every config is validated on construction (``ValueError``
    naming the key, the value and the allowed range). Two configs are equal when their keys
    and values are (comments aside) and their work budgets are.

    ``origin`` is the name errors give it, ``base_dir`` the folder relative paths in it (a
    measured profile) start from, ``changes`` the dotted keys set by :meth:`replace` or
    :func:`rvlife.grid` since its source, ``work_budget_min`` the work budget (minutes of
    estimated computing on 2 cores; work beyond it is refused before it starts).
    """

    def __init__(
        self,
        toml: str,
        origin: str = "<string>",
        base_dir: Optional[PathLike] = None,
        *,
        work_budget_min: float = DEFAULT_WORK_BUDGET_MIN,
        changes: Optional[Mapping[str, Any]] = None,
    ):
        self._toml = toml
        self.origin: str = origin
        self.base_dir: Optional[str] = None if base_dir is None else os.fspath(base_dir)
        self.work_budget_min: float = float(work_budget_min)
        self.changes: Dict[str, Any] = dict(changes or {})
        # Parsed and validated once; every call reuses it.
        self._loaded = _rvlife.load(toml, origin, self.base_dir, self.work_budget_min)

    @property
    def toml(self) -> str:
        """The config's TOML text (comments kept through edits)."""
        return self._toml

    @classmethod
    def from_file(cls, path: PathLike, *, work_budget_min: float = DEFAULT_WORK_BUDGET_MIN) -> "Config":
        """The config file at ``path`` (relative paths in it start from its folder)."""
        p = Path(path)
        try:
            text = p.read_text()
        except OSError as e:
            raise ValueError(f"config {p}: cannot read the file: {e}") from e
        return cls(text, str(p), p.parent, work_budget_min=work_budget_min)

    @classmethod
    def from_toml(cls, text: str, origin: str = "<string>", *, work_budget_min: float = DEFAULT_WORK_BUDGET_MIN) -> "Config":
        """A config from TOML text (a whole config)."""
        return cls(text, origin, work_budget_min=work_budget_min)

    @classmethod
    def from_dict(cls, sections: Mapping[str, Any], base: Optional["Config"] = None, origin: Optional[str] = None) -> "Config":
        """``sections`` (``{"cycloid": {"eccentricity_mm": 1.2}}``, as the TOML file nests
        them) merged over ``base`` (default: the built-in example) as a JSON merge patch: a
        dict merges into the section or table it names, any other value replaces, ``None``
        removes a key (back to its default). A whole config given as a dict gives that config
        wherever it sets every key the base sets."""
        b = base if base is not None else _example("rv-40e")
        text = _rvlife.config_merge(b.toml, origin or b.origin, _json(dict(sections)))
        changes = dict(b.changes)
        changes.update(_flatten(sections))
        return cls(
            text,
            origin or f"{b.origin} with a dict",
            b.base_dir,
            work_budget_min=b.work_budget_min,
            changes=changes,
        )

    def replace(self, changes: Optional[Mapping[str, Any]] = None, **keys: Any) -> "Config":
        """A new config with each dotted key (``"cycloid.eccentricity_mm"``) set to its value
        whole (a number keeps the integer or float type of the value it replaces; ``None``
        removes the key); comments and layout kept. Keys may also be given as keyword
        arguments with ``__`` for the dots (``cycloid__eccentricity_mm=1.2``). ``ValueError``
        names a key that is not a config key, or a value out of its range."""
        edits: Dict[str, Any] = dict(changes or {})
        edits.update({k.replace("__", "."): v for k, v in keys.items()})
        text = _rvlife.config_set(self._toml, self.origin, _json(edits))
        merged = dict(self.changes)
        merged.update(edits)
        return Config(text, self.origin, self.base_dir, work_budget_min=self.work_budget_min, changes=merged)

    def with_work_budget(self, minutes: float) -> "Config":
        """The same config with another work budget (minutes of estimated computing on 2
        cores; the command line's ``--work-budget-min``)."""
        return Config(self._toml, self.origin, self.base_dir, work_budget_min=minutes, changes=self.changes)

    def get(self, key: str, default: Any = None) -> Any:
        """The value of a dotted key as written in the config (``default`` when the config
        does not write it: the library's default applies)."""
        v: Any = self.to_dict()
        for part in key.split("."):
            if not isinstance(v, dict) or part not in v:
                return default
            v = v[part]
        return v

    def to_dict(self) -> Dict[str, Any]:
        """The config as a dict of sections (what :meth:`from_dict` takes)."""
        d: Dict[str, Any] = _rvlife.config_to_dict(self._toml, self.origin)
        return _plain(d)

    def to_toml(self) -> str:
        """The config as TOML text (comments kept); ``rvlife run`` reads it as a file."""
        return self._toml

    def write(self, path: PathLike) -> Path:
        """Writes :meth:`to_toml` to ``path``; returns the path."""
        p = Path(path)
        p.write_text(self._toml)
        return p

    def _key(self) -> Tuple[str, float]:
        return (json.dumps(self.to_dict(), sort_keys=True), self.work_budget_min)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Config):
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())

    def _text(self) -> Tuple[str, str, Optional[str], float]:
        """What rebuilds the config elsewhere (a Dask worker): text, origin, folder, budget."""
        return (self._toml, self.origin, self.base_dir, self.work_budget_min)

    def __getstate__(self) -> Dict[str, Any]:
        return {"text": self._text(), "changes": self.changes}

    def __setstate__(self, state: Dict[str, Any]) -> None:
        toml, origin, base_dir, budget = state["text"]
        self.__init__(toml, origin, base_dir, work_budget_min=budget, changes=state["changes"])  # type: ignore[misc]

    def __repr__(self) -> str:
        shown = ", ".join(f"{k}={v!r}" for k, v in list(self.changes.items())[:4])
        more = ", ..." if len(self.changes) > 4 else ""
        changed = f" with {shown}{more}" if shown else ""
        return f"Config({self.origin!r}{changed})"


def _flatten(d: Mapping[str, Any], prefix: str = "") -> Dict[str, Any]:
    out: Dict[str, Any] = {}
    for k, v in d.items():
        key = f"{prefix}{k}"
        if isinstance(v, Mapping):
            out.update(_flatten(v, key + "."))
        else:
            out[key] = v
    return out


@functools.lru_cache(maxsize=None)
def _example(preset: str) -> Config:
    return Config(_rvlife.example_toml(preset), f"<built-in {preset}>")


def example(preset: str = "rv-40e") -> Config:
    """A built-in config (``rvlife example --preset``): ``rv-40e`` (the default, the built-in
    example), ``paper`` (the paper's reducer as printed), ``rv-20e``, ``rv-80e``,
    ``single-stage``; :func:`presets` lists them."""
    return _example(preset)


def presets() -> List[Tuple[str, str]]:
    """``(name, summary)`` of every built-in config."""
    return list(_rvlife.presets())
