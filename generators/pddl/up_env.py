"""Lean access to unified-planning.

``unified_planning.engines`` imports ConfigSpace at module level, which pulls in scipy.stats
and costs seconds per process, only to annotate ``Engine.get_configuration_space``. kitkb
never asks for configuration spaces, so :func:`environment` registers a stand-in module that
imports the real ConfigSpace the first time anything in it is actually used.
"""

from __future__ import annotations

import importlib
import sys
import types
from typing import Any


class _LazyConfigSpace(types.ModuleType):
    """Stand-in for the ConfigSpace package: loads the real one on first real use."""

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        return getattr(_real_configspace(), name)


def _real_configspace() -> types.ModuleType:
    if isinstance(sys.modules.get("ConfigSpace"), _LazyConfigSpace):
        del sys.modules["ConfigSpace"]
    return importlib.import_module("ConfigSpace")


class _ConfigurationSpace:
    """Placeholder class; instantiating it returns a real ``ConfigurationSpace``."""

    def __new__(cls, *args: Any, **kwargs: Any) -> Any:
        return _real_configspace().ConfigurationSpace(*args, **kwargs)


def _install_stand_in() -> None:
    if "ConfigSpace" in sys.modules or "unified_planning.engines" in sys.modules:
        return
    module = _LazyConfigSpace("ConfigSpace")
    module.ConfigurationSpace = _ConfigurationSpace  # type: ignore[attr-defined]
    sys.modules["ConfigSpace"] = module


def environment() -> Any:
    """unified-planning's global environment, credits silenced, imported cheaply."""
    _install_stand_in()
    from unified_planning.environment import get_environment

    env = get_environment()
    env.credits_stream = None
    return env
