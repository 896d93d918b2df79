"""The registry of cells: a cell is opened from its URL, by the opener of the URL's scheme.

    >>> cell = open_cell("sim:?faults=missed-grasp@6&seed=1", CellRequest(scene=scene))  # doctest: +SKIP
    >>> cell = open_cell("kitkb://127.0.0.1:3989")                                        # doctest: +SKIP
    >>> cell = open_cell("crcl://robot.lab:64444?sensor=camera.lab:3989")                 # doctest: +SKIP

Every cell is built from one thing, its URL, by one factory (:func:`open_cell`), plus what a
simulated cell needs from the inputs the caller has ALREADY READ (a :class:`CellRequest`: the
initial state's scene, faults, seed, the sensor's accuracy). Schemes (:func:`cell_schemes`):

``sim:`` (the default, :data:`DEFAULT_URL`)
    kitkb's in-process simulator (:class:`kb.sim.SimulatedCell`) holding ``request.scene``;
    query parameters ``faults=`` (``missed-grasp=0.2,part-missing@3``), ``seed=`` and
    ``noise=`` (``position=1mm,orientation=0.5deg``, over ``request.accuracy``) may stand for
    the request's (a parameter and a different request value at once are refused). Every
    capability, ground truth included.
``mujoco:``
    the physics-based cell on MuJoCo (:class:`kb.physics.MujocoCell`, docs/physics.md), with
    ``sim:``'s parameters and capabilities; its ground truth is where MuJoCo brought things to rest.
``kitkb://HOST[:PORT][?command=PORT&timeout=S]``
    a kitkb cell server (``kitkb sim serve``): PORT is its sensor port (default 3989), its
    command port PORT + 1 or ``command=``; :class:`kb.crcl.RemoteCell`. It moves, senses,
    inspects and hears each action; no ground truth. The old ``HOST:PORT[,COMMAND_PORT]``
    is this scheme.
``crcl://HOST[:PORT]?sensor=HOST[:PORT][&timeout=S]``
    a CRCL 1.x controller (PORT default 64444, NIST's) paired with a USARTruth-style pose
    sensor (default port 3989): it moves, senses and announces each action as a CRCL Message;
    no inspection, no ground truth (:class:`kb.cells.remote.CrclCell`).

Other distributions add schemes through the entry-point group :data:`ENTRY_POINT_GROUP`
(``kitkb.cells``): ``scheme = "module:function"``, the function taking ``(url: CellURL,
request: CellRequest)`` and returning a cell (a physics engine, a ROS 2 bridge). Built-in
schemes are registered by module name (:data:`BUILTIN`) and imported when first opened, as
:mod:`kb.core.generators` finds generators: this module imports no cell, so the executor,
which sits below the simulator, never imports ``kb.sim`` through it.

An opener may carry a ``check(url, request)`` function attribute that validates both without
opening anything (:func:`check_cell`: a campaign checks its options before any trial runs).
A URL that does not parse, an unknown scheme, a parameter the scheme does not take and a cell
that does not answer are each an :class:`~kb.core.errors.InputError` (exit 2), one line
naming the URL and the known schemes. What a cell can do is a set of capabilities
(:mod:`kb.crcl.cell`); the executor refuses a cell that lacks one its run needs.
"""

from __future__ import annotations

import importlib
import re
import socket
from dataclasses import dataclass, field
from importlib.metadata import entry_points
from pathlib import Path
from typing import Any, Callable, Mapping, Protocol, runtime_checkable
from urllib.parse import parse_qsl, urlsplit

from kb.cells.accuracy import SensorAccuracy
from kb.core.errors import InputError
from kb.spatial.scene import Scene

#: Entry point group through which other distributions register cell schemes.
ENTRY_POINT_GROUP = "kitkb.cells"
#: kitkb's own schemes: scheme -> (module, function), imported when a URL of it is first opened.
BUILTIN: dict[str, tuple[str, str]] = {
    "sim": ("kb.sim.cell", "open_simulated"),
    "mujoco": ("kb.physics.cell", "open_mujoco"),
    "kitkb": ("kb.cells.remote", "open_kitkb"),
    "crcl": ("kb.cells.remote", "open_crcl"),
}
#: the cell a run has when none is named: the in-process simulator
DEFAULT_URL = "sim:"
#: the old ``--cell`` address: ``HOST:PORT`` or ``HOST:SENSOR_PORT,COMMAND_PORT`` (kitkb://)
_ADDRESS = re.compile(r"^(?P<host>\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9._-]+):(?P<port>\d+)(?:,(?P<command>\d+))?$")
_SCHEME = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*:")


@dataclass(frozen=True)
class CellRequest:
    """What the caller has already read that a cell may need (each input is read once, by the
    caller; an opener reads no file of the run).

    ``scene``: the state the cell holds, as :class:`~kb.spatial.scene.Scene` (built with the
    declared goal and ``match_names``; for a simulated cell, its ground truth: the initial
    state, or the real placement when it differs from the nominal one); ``faults``: what a
    simulated cell injects (a ``FaultSpec`` or its text); ``fault_kinds``: the kinds that text
    names (the run's domain's :class:`kb.model.faults.FaultKinds`; None: the shipped domain's);
    ``seed``: of its faults and sensor
    noise (None: not given, 0); ``accuracy``: the sensor's accuracy (a simulated sensor has
    it; with a real cell what the executor assumes); ``state`` / ``goal``: the files the run's
    inputs came from (for messages, and for a cell of another package that wants paths);
    ``match_names``: state and goal matched by local name; ``timeout``: seconds a remote cell
    is waited for (None: the named limits)."""

    scene: Scene | None = None
    faults: Any = None
    fault_kinds: Any = None
    seed: int | None = None
    accuracy: SensorAccuracy | None = None
    state: Path | None = None
    goal: Path | None = None
    match_names: bool = False
    timeout: float | None = None


@dataclass(frozen=True)
class CellURL:
    """A parsed cell URL: ``text`` as given, ``scheme`` (lower case), ``host`` and ``port``
    (None when absent), ``path``, ``params`` (the query, each name once)."""

    text: str
    scheme: str
    host: str | None = None
    port: int | None = None
    path: str = ""
    params: Mapping[str, str] = field(default_factory=dict)

    def refuse(self, why: str) -> InputError:
        """The one-line error for this URL: ``why`` (kept as the error's ``reason``), and the
        schemes known."""
        error = InputError(f"cell {self.text!r}: {why} (known schemes: {', '.join(cell_schemes())})")
        error.reason = why  # type: ignore[attr-defined]
        return error

    def only(self, *names: str) -> None:
        """Refuse a query parameter other than ``names``."""
        extra = sorted(set(self.params) - set(names))
        if extra:
            known = ", ".join(names) if names else "none"
            raise self.refuse(f"unknown parameter {extra[0]!r} for {self.scheme}: (it takes: {known})")

    def number(self, name: str, kind: Callable[[str], Any] = float) -> Any:
        """Parameter ``name`` as a number (None when absent); refused when it is none."""
        raw = self.params.get(name)
        if raw is None:
            return None
        try:
            value = kind(raw)
        except ValueError:
            raise self.refuse(f"{name}={raw!r} is not a {'whole ' if kind is int else ''}number") from None
        if value < 0 or value != value:
            raise self.refuse(f"{name}={raw!r} must not be negative")
        return value


@runtime_checkable
class KnowsAccuracy(Protocol):
    """A cell that says what its sensor's accuracy is (a simulated one: the noise it adds)."""

    @property
    def accuracy(self) -> SensorAccuracy | None: ...


@runtime_checkable
class Closes(Protocol):
    """A cell holding connections or processes, closed when the run is done."""

    def close(self) -> None: ...


def cell_schemes() -> list[str]:
    """Every scheme :func:`open_cell` knows (built-in and through the entry-point group)."""
    return sorted(_registered())


def parse_cell_url(text: str) -> CellURL:
    """The :class:`CellURL` of ``text``: a URL of a scheme, or the old ``HOST:PORT[,PORT]``
    (``kitkb://``). An InputError for what is no URL."""
    text = (text or "").strip()
    old = _ADDRESS.match(text)
    if old:
        params = {"command": old.group("command")} if old.group("command") else {}
        return CellURL(text, "kitkb", old.group("host").strip("[]"), int(old.group("port")), "", params)
    if not _SCHEME.match(text):
        raise CellURL(text, "").refuse("not a cell URL (SCHEME:..., or HOST:PORT for a kitkb cell server)")
    try:
        parts = urlsplit(text)
        port = parts.port
    except ValueError as exc:
        raise CellURL(text, "").refuse(f"not a cell URL: {exc}") from None
    pairs = parse_qsl(parts.query, keep_blank_values=True)
    params: dict[str, str] = {}
    for key, value in pairs:
        if key in params:
            raise CellURL(text, parts.scheme.lower()).refuse(f"parameter {key!r} given twice")
        params[key] = value
    return CellURL(text, parts.scheme.lower(), parts.hostname, port, parts.path, params)


def open_cell(url: str | CellURL | None = None, request: CellRequest | None = None) -> Any:
    """The cell of ``url`` (default :data:`DEFAULT_URL`, the in-process simulator), opened by
    its scheme's opener with ``request`` (what the caller has read: a simulated cell needs
    ``request.scene``). The cell has the capabilities of :mod:`kb.crcl.cell` that its kind
    has; a cell that :class:`Closes` is the caller's to close (:func:`close_cell`).

    An InputError (exit 2), one line naming the URL and the known schemes, for a URL that does
    not parse, an unknown scheme or parameter, and a cell that does not answer."""
    parsed = url if isinstance(url, CellURL) else parse_cell_url(DEFAULT_URL if url is None else url)
    opener = _opener(parsed)
    cell = opener(parsed, request or CellRequest())
    if getattr(cell, "url", None) is None:
        try:
            cell.url = parsed.text
        except AttributeError:  # a cell with slots: named by its type in messages
            pass
    return cell


def check_cell(url: str | CellURL | None = None, request: CellRequest | None = None) -> CellURL:
    """Check ``url`` and ``request`` without opening the cell: the URL parses, its scheme is
    known, and the opener's ``check`` (a function attribute of the opener, when it has one:
    ``sim:`` checks its faults, seed and noise) accepts them. The parsed URL; an InputError
    as :func:`open_cell` gives."""
    parsed = url if isinstance(url, CellURL) else parse_cell_url(DEFAULT_URL if url is None else url)
    check = getattr(_opener(parsed), "check", None)
    if callable(check):
        check(parsed, request or CellRequest())
    return parsed


def close_cell(cell: Any) -> None:
    """Close ``cell`` when it holds anything (:class:`Closes`)."""
    if isinstance(cell, Closes):
        cell.close()


def cell_accuracy(cell: Any, assumed: SensorAccuracy | None) -> SensorAccuracy | None:
    """The accuracy the executor should verify with on ``cell``: the cell's own when it
    :class:`KnowsAccuracy` (a simulated cell's noise, its URL's ``noise=`` included), else
    ``assumed`` (what the state or ``--sensor-noise`` says)."""
    if isinstance(cell, KnowsAccuracy):
        return cell.accuracy
    return assumed


def reach(url: CellURL, host: str, port: int, timeout: float | None) -> None:
    """Refuse ``url`` when nothing accepts a connection at ``host:port`` within ``timeout``
    seconds (5 when None); the connection made is closed at once."""
    try:
        socket.create_connection((host, port), timeout=timeout if timeout is not None else 5.0).close()
    except OSError as exc:
        why = exc.strerror or type(exc).__name__
        raise url.refuse(f"nothing answers at {host}:{port} ({why})") from None


def _registered() -> dict[str, str]:
    """Every known scheme -> ``module:function`` (built-in schemes win)."""
    found = {ep.name.lower(): ep.value for ep in entry_points(group=ENTRY_POINT_GROUP)}
    found.update({name: f"{module}:{fn}" for name, (module, fn) in BUILTIN.items()})
    return found


def _opener(url: CellURL) -> Callable[[CellURL, CellRequest], Any]:
    spec = _registered().get(url.scheme)
    if spec is None:
        raise url.refuse(f"unknown scheme {url.scheme!r}")
    module, _, name = spec.partition(":")
    try:
        found = getattr(importlib.import_module(module), name)
    except (ImportError, AttributeError) as exc:
        raise url.refuse(f"the opener of {url.scheme}: ({spec}) cannot be loaded: {exc}") from None
    if not callable(found):
        raise url.refuse(f"the opener of {url.scheme}: ({spec}) is not callable")
    return found
