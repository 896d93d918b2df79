"""Find the shipped ontology and shape files, in a wheel or in a source checkout."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

_REPO_TOP = Path(__file__).resolve().parents[2]


def _data_dir(kind: str) -> Path:
    packaged = Path(str(resources.files("kb"))) / "_data" / kind
    if packaged.is_dir():
        return packaged
    return _REPO_TOP / kind


def ontologies_dir() -> Path:
    """Folder of the shipped ontologies (``kitting.ttl``, ``soap.ttl``, ``scenarios/``)."""
    return _data_dir("ontologies")


def shapes_dir() -> Path:
    """Folder of the shipped SHACL shapes."""
    return _data_dir("shapes")


def ontology_path(name: str) -> Path:
    """Path of a shipped ontology file, e.g. ``ontology_path("kitting.ttl")``."""
    return ontologies_dir() / name


def shapes_path(name: str) -> Path:
    """Path of a shipped shapes file, e.g. ``shapes_path("kitting-shapes.ttl")``."""
    return shapes_dir() / name


def model_files() -> list[Path]:
    """The shipped model ontologies (kitting and SOAP) that the database schema is made from."""
    return [p for p in (ontology_path("kitting.ttl"), ontology_path("soap.ttl")) if p.is_file()]


def scenario_dirs() -> list[Path]:
    """The shipped scenario folders (each holds ``init.ttl`` and ``goal.ttl``)."""
    root = ontologies_dir() / "scenarios"
    return sorted(p for p in root.iterdir() if p.is_dir()) if root.is_dir() else []
