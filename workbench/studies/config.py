"""Typed, frozen configurations of the studies: the part they share (output folders, JSON in and out).

One record per study sits beside its study (:mod:`workbench.studies.convergence_config`,
:mod:`workbench.studies.stability_config`, :mod:`workbench.studies.bench_config`,
:mod:`workbench.studies.convective_table_config`, :mod:`workbench.studies.validity_config`), like a case record:
the defaults are the study as published, a study's ``main(argv)`` builds its record from the command-line options,
and ``run_*`` takes it. Every study writes its record into its JSON (``"config"``: :func:`to_json`), so a report
reads what the study ran with from the JSON alone; :func:`from_json` reads it back (defaults for keys an older JSON
lacks).

These modules are light (no dolfinx): the studies and their reports both import them, and neither imports the
other. Units: h_c and levels are fractions of the classical contact half-width; kappa0, gamma0 are
dimensionless (kappa = kappa0 E / h); times in s.
"""

from __future__ import annotations

from dataclasses import fields
from pathlib import Path
from typing import Any, ClassVar

from workbench.paths import default_paths

__all__ = ["StudyFolders", "folder", "from_json", "is_decreasing", "to_json"]


def is_decreasing(values) -> bool:
    """Every value strictly below the one before it."""
    return all(b < a for a, b in zip(values, values[1:], strict=False))


def folder(given: Path | None, default: Path) -> Path:
    """``given`` (absolute), else the workbench default: never the working directory."""
    return Path(given).expanduser().resolve() if given is not None else default


class StudyFolders:
    """The folders of a study's config (a mixin of the frozen config dataclasses, whose fields ``out`` and
    ``mesh_cache`` it reads): ``out_dir`` is ``out``, else ``<results>/<study>``; ``cache_dir`` is ``mesh_cache``,
    else ``<results>/mesh_cache``."""

    study: ClassVar[str]

    @property
    def out_dir(self) -> Path:
        """The output folder: ``out``, else ``<results>/<study>``."""
        return folder(self.out, default_paths().study(self.study))

    @property
    def cache_dir(self) -> Path:
        """The mesh cache: ``mesh_cache``, else ``<results>/mesh_cache``."""
        return folder(self.mesh_cache, default_paths().mesh_cache)


def to_json(cfg) -> dict[str, Any]:
    """The config as a JSON-ready dict (paths as strings; tuples become lists when dumped)."""
    out = {}
    for f in fields(cfg):
        v = getattr(cfg, f.name)
        out[f.name] = str(v) if isinstance(v, Path) else v
    return out


def _tuples(v: Any) -> Any:
    """JSON lists back to tuples, also inside dicts (every sequence of a config is a tuple)."""
    if isinstance(v, list):
        return tuple(_tuples(x) for x in v)
    if isinstance(v, dict):
        return {k: _tuples(x) for k, x in v.items()}
    return v


def from_json(cls: type, data: dict | None, *, strict: bool = False):
    """A config of class ``cls`` from its JSON dict; keys it lacks take their defaults.

    Args:
        cls: One of the config classes.
        data: The ``"config"`` entry of a study JSON (None: the defaults).
        strict: Unknown keys are errors (else they are ignored: a newer JSON read by an older report).

    Raises:
        ValueError: an unknown key (strict), or a value out of range.
    """
    data = data or {}
    known = {f.name: f for f in fields(cls)}
    unknown = sorted(set(data) - set(known))
    if unknown and strict:
        raise ValueError(f"{cls.__name__}: unknown keys {unknown}; allowed keys: {', '.join(known)}")
    kw = {}
    for name, value in data.items():
        if name not in known:
            continue
        if name in ("out", "mesh_cache") and value is not None:
            value = Path(value)
        else:
            value = _tuples(value)
        kw[name] = value
    return cls(**kw)
