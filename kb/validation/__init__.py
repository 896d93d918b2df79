"""Validation of ontology files: closed-world rules and SHACL with ``file:line`` reports.

:func:`validate` is the entry point (``kitkb validate``): :mod:`.validator` runs it,
:mod:`.rules` holds the checks that are not per-class shapes, :mod:`.shapes` derives the
SHACL shapes of an OWL model, :mod:`.report` turns SHACL results into diagnostics with
lines and compact names, :mod:`.suggest` finds "did you mean" names.
:mod:`.consistency` checks open-world consistency with HermiT (owlready2, Java).
"""

from kb.validation.validator import ValidationReport, default_files, validate

__all__ = ["ValidationReport", "default_files", "validate"]
