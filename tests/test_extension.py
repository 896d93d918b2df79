"""Issue 28, "Done when": a domain extension written only in Turtle runs end to end.

Two extensions of different shapes (tests/data/extension/), each given with ``--domain`` exactly
as kitkb's own ``kitting-domain.ttl`` is read (one reader adds them to it), through the command
line: validate, generate pddl, plan, run (a seeded fault of the kind the extension declares or
extends, diagnosed as the extension's failure mode, recovered by its recovery plan, the goal
from geometry, the kit scored), and the test methods. No kitkb code knows their names.

* ``bin``: parts wait in an inspection bin (``ktw:PartsBin``); ``take-part-from-bin`` with its
  CRCL program, ``part-location-partsbin`` defined by a new intermediate relation over the RCC8
  primitives (``relations.ttl``, a model file imported by file name), the failure mode
  ``missed-bin-grasp`` remedied by a recovery plan, the fault kind ``empty-bin-grasp``.
* ``buffer``: a stray part on the work table keeps it from being empty; ``park-part`` carries
  it into a buffer box (``xp:BufferBox``, a class the extension declares under
  ``ktw:LargeContainer``, which the state files type the box with), its effect a shipped predicate
  (``worktable-empty``); ``part-on-worktable`` quantifies over end effectors and holders; the
  precondition mode ``stray-part-gone`` runs a recovery plan bound by ``soap:ParameterBinding``
  and then replans; the shipped fault kind ``part-missing`` is extended to strike ``park-part``.

And broken extensions are refused with one line naming the file and line, exit 2.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from kb.cli import main

pytestmark = pytest.mark.usefixtures("own_directory")

DATA = Path(__file__).parent / "data" / "extension"
BIN, BUFFER = DATA / "bin", DATA / "buffer"


def _args(ext: Path) -> list[str]:
    return [str(ext / "init.ttl"), str(ext / "goal.ttl"), "--domain", str(ext / "extension.ttl")]


def _run(ext: Path, tmp_path: Path, *more: str) -> dict:
    report = tmp_path / "report.json"
    assert main(["-q", "run", *_args(ext), "-o", str(tmp_path / "out"), "--report", str(report), *more]) == 0
    return json.loads(report.read_text())


def _done(report: dict) -> list[str]:
    return [e["action"] for e in report["timeline"] if e.get("kind") == "action" and e.get("status") == "done"]


# --- validate, generate, plan --------------------------------------------------------------

@pytest.mark.parametrize("ext", [BIN, BUFFER], ids=["bin", "buffer"])
def test_the_extension_and_its_states_validate(ext: Path, capsys) -> None:
    assert main(["validate", str(ext / "extension.ttl"), str(ext / "init.ttl"), str(ext / "goal.ttl")]) == 0
    assert "conforms" in capsys.readouterr().out


@pytest.mark.parametrize("ext, action, predicates, init_fact", [
    (BIN, "take-part-from-bin", ("part-location-partsbin",), "(part-location-partsbin part_b_1 inspection_bin)"),
    (BUFFER, "park-part", ("part-on-worktable", "part-location-buffer"), "(part-on-worktable part_a_4 work_table_1)"),
], ids=["bin", "buffer"])
def test_generated_pddl_has_the_new_action_and_predicates_beside_the_shipped_ones(
        ext: Path, action: str, predicates: tuple[str, ...], init_fact: str, tmp_path: Path) -> None:
    assert main(["-q", "generate", "pddl", *_args(ext), "-o", str(tmp_path)]) == 0
    domain = (tmp_path / "domain.pddl").read_text()
    problem = (tmp_path / "problem.pddl").read_text()
    assert f"(:action {action}" in domain
    assert "(:action take-part" in domain and "(:action put-kit" in domain  # added to, not instead of, kitkb's
    for p in predicates:
        assert f"({p} " in domain
    # the initial fact of the new predicate is decided by its definition on the state's geometry
    assert init_fact in re.sub(r"\s+", " ", problem)


@pytest.mark.parametrize("ext, action", [(BIN, "take-part-from-bin"), (BUFFER, "park-part")], ids=["bin", "buffer"])
def test_the_plan_uses_the_new_action(ext: Path, action: str, tmp_path: Path) -> None:
    plan = tmp_path / "plan.txt"
    assert main(["-q", "plan", *_args(ext), "-o", str(plan)]) == 0
    lines = [ln for ln in plan.read_text().splitlines() if ln.startswith("(")]
    assert any(ln.startswith(f"({action} ") for ln in lines)


def test_without_the_extension_the_state_has_no_plan(tmp_path: Path) -> None:
    """The bin's parts cannot be taken by kitkb's own actions: the extension is what plans it."""
    code = main(["-q", "plan", str(BIN / "init.ttl"), str(BIN / "goal.ttl"), "-o", str(tmp_path / "p.txt")])
    assert code == 1


# --- run: execute, diagnose, recover, score ------------------------------------------------

def test_bin_runs_and_builds_the_kit(tmp_path: Path) -> None:
    report = _run(BIN, tmp_path)
    assert report["goal_holds"] and report["stopped"] is None
    assert "take-part-from-bin" in _done(report)
    assert report["failures"] == []
    assert [(k["kit"], k["score"], k["max_score"]) for k in report["kits"]] == [("kit_1", 6, 6)]


def test_bin_fault_is_diagnosed_as_the_new_mode_and_its_recovery_plan_runs(tmp_path: Path) -> None:
    report = _run(BIN, tmp_path, "--faults", "empty-bin-grasp@0", "--seed", "3")
    assert [x["kind"] for x in report["injected"]] == ["empty-bin-grasp"]
    [failure] = report["failures"]
    assert failure["mode"] == "missed-bin-grasp" and failure["action"] == "take-part-from-bin"
    assert failure["phase"] == "effect" and failure["recovery"] == "recovery-plan"
    assert failure["notifications"][0]["message"].startswith("missed grasp of part_b_1 in bin inspection_bin")
    done = _done(report)
    taken = [i for i, a in enumerate(done) if a == "take-part-from-bin"]
    assert len(taken) == 1 and done[taken[0] + 1] == "put-part"  # the recovery plan's step, then the plan
    assert report["goal_holds"] and report["stopped"] is None
    assert report["kits"][0]["score"] == report["kits"][0]["max_score"]
    from kb.execution.inputs import DomainInputs
    from kb.execution.quality import score_detection
    from kb.model.faults import fault_kinds

    kinds = fault_kinds(DomainInputs([BIN / "extension.ttl"]).kb)
    row = score_detection([report], kinds).as_dict()["kinds"]["empty-bin-grasp"]
    assert row["injected"] == 1 and row["diagnosed_right"] == 1 and row["missed"] == 0


def test_a_defective_part_in_the_bin_is_found_by_the_extension_s_inspection_and_replaced(tmp_path: Path) -> None:
    """look-in-bin's effect is an inspection (a sensor atom) of take-part-from-bin's part: the
    executor inspects the part before taking it, as it does for kitkb's take-part, and the
    extension's mode condemns it and binds another of its SKU from the bin."""
    report = _run(BIN, tmp_path, "--faults", "defective-part@0")
    assert [x["kind"] for x in report["injected"]] == ["defective-part"]
    [failure] = report["failures"]
    assert (failure["mode"], failure["action"], failure["recovery"]) == ("defective-bin-part", "look-in-bin", "rebind")
    taken = [e["args"][1] for e in report["timeline"] if e.get("kind") == "action"
             and e.get("action") == "take-part-from-bin" and e.get("status") == "done"]
    assert taken == ["part_b_2"]  # part_b_1 failed inspection: never taken
    assert report["goal_holds"] and report["kits"][0]["score"] == 6


def test_the_numeric_domain_has_the_extension_s_function_and_numeric_effect(tmp_path: Path) -> None:
    assert main(["-q", "generate", "pddl", *_args(BIN), "--encoding", "numeric", "-o", str(tmp_path)]) == 0
    domain = re.sub(r"\s+", " ", (tmp_path / "domain.pddl").read_text())
    problem = re.sub(r"\s+", " ", (tmp_path / "problem.pddl").read_text())
    assert "(quantity-partsbin ?" in domain and "(decrease (quantity-partsbin ?partsbin) 1)" in domain
    assert "(= (quantity-partsbin inspection_bin) 3)" in problem  # counted by its definition


def test_buffer_runs_and_parks_the_stray_part_before_the_kit_tray_goes_on_the_table(tmp_path: Path) -> None:
    report = _run(BUFFER, tmp_path)
    done = _done(report)
    assert done.index("park-part") < done.index("put-kittray")
    assert report["goal_holds"] and report["failures"] == []
    assert report["kits"][0]["score"] == 6


def test_buffer_precondition_mode_runs_its_bound_recovery_plan_then_replans(tmp_path: Path) -> None:
    report = _run(BUFFER, tmp_path, "--faults", "part-missing@0")
    assert [(x["kind"], x["objects"]) for x in report["injected"]] == [("part-missing", ["part_a_4"])]
    [failure] = report["failures"]
    assert (failure["mode"], failure["action"], failure["phase"]) == ("stray-part-gone", "park-part", "precondition")
    assert failure["outcome"].startswith("recovered: recovery plan (remove-endeffector robot_1 part_gripper ")
    assert report["replans"] == 1
    done = _done(report)
    assert "park-part" not in done  # nothing left to park: the new plan goes straight on
    assert done[1] == "remove-endeffector"  # the recovery plan's step, its effector bound from the failed action
    assert report["goal_holds"] and report["kits"][0]["score"] == 6


# --- the test methods ----------------------------------------------------------------------

@pytest.mark.slow
def test_a_test_method_campaign_reads_the_extension(tmp_path: Path, capsys) -> None:
    """The errors method with the extension: its fault kind is accepted in --faults beside a
    shipped one (it strikes no action of the method's generated cells, which have no bin), and
    the campaign builds its kit."""
    out = tmp_path / "campaign"
    code = main(["-q", "testmethod", "errors", "--trials", "1", "--seed", "5", "--workers", "1", "--domain",
                 str(BIN / "extension.ttl"), "--faults", "empty-bin-grasp=0.5,dropped-part=0.2", "--out", str(out)])
    assert code == 0, capsys.readouterr().err
    summary = json.loads((out / "campaign.json").read_text())
    assert summary["trials"] == 1 and summary["summary"]["kits_built"] == 1


# --- broken extensions: one line at file:line, exit 2 --------------------------------------

def _broken(tmp_path: Path, old: str, new: str) -> Path:
    text = (BIN / "extension.ttl").read_text()
    assert text.count(old) == 1
    path = tmp_path / "broken.ttl"
    path.write_text(text.replace(old, new))
    (tmp_path / "relations.ttl").write_text((BIN / "relations.ttl").read_text())
    return path


def _line_of(path: Path, needle: str) -> int:
    return next(i for i, ln in enumerate(path.read_text().splitlines(), 1) if needle in ln)


@pytest.mark.parametrize("command", ["generate", "plan", "run"])
def test_a_syntax_error_is_refused_at_its_line(command: str, tmp_path: Path, capsys) -> None:
    ext = _broken(tmp_path, 'soap:hasCommandStep_Command "CloseGripper" .', 'soap:hasCommandStep_Command "CloseGripper .')
    argv = {"generate": ["generate", "pddl", "-o", str(tmp_path / "o")], "plan": ["plan", "-o", str(tmp_path / "p.txt")],
            "run": ["run", "-o", str(tmp_path / "o")]}[command]
    assert main([*argv, str(BIN / "init.ttl"), str(BIN / "goal.ttl"), "--domain", str(ext)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and re.match(rf"{re.escape(str(ext))}:\d+: ", err[0]), err


@pytest.mark.parametrize("command", ["generate", "plan", "run"])
def test_an_undefined_predicate_in_a_precondition_is_refused_at_its_line(command: str, tmp_path: Path, capsys) -> None:
    ext = _broken(tmp_path, "soap:hasPredicateAtom_Predicate xb:part-location-partsbin ;\n"
                  "    soap:hasPredicateAtom_ReferenceParameter xb:take-part-from-bin_part ;\n"
                  "    soap:hasPredicateAtom_TargetParameter xb:take-part-from-bin_partsbin ;\n"
                  "    soap:hasAtom_IsNegated false .\nxb:take-part-from-bin_pre_robot-empty",
                  "soap:hasPredicateAtom_Predicate xb:part-location-partsbox ;\n"
                  "    soap:hasPredicateAtom_ReferenceParameter xb:take-part-from-bin_part ;\n"
                  "    soap:hasPredicateAtom_TargetParameter xb:take-part-from-bin_partsbin ;\n"
                  "    soap:hasAtom_IsNegated false .\nxb:take-part-from-bin_pre_robot-empty")
    argv = {"generate": ["generate", "pddl", "-o", str(tmp_path / "o")], "plan": ["plan", "-o", str(tmp_path / "p.txt")],
            "run": ["run", "-o", str(tmp_path / "o")]}[command]
    assert main([*argv, str(BIN / "init.ttl"), str(BIN / "goal.ttl"), "--domain", str(ext)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    line = _line_of(ext, "xb:part-location-partsbox")
    assert len(err) == 1 and err[0].startswith(f"{ext}:"), err
    assert "part-location-partsbox" in err[0]
    assert int(err[0].split(":")[1]) in (line, line - 1), err  # the atom's statement


def test_an_unknown_program_command_is_refused_at_its_line(tmp_path: Path, capsys) -> None:
    ext = _broken(tmp_path, 'soap:hasCommandStep_Command "CloseGripper" .', 'soap:hasCommandStep_Command "Teleport" .')
    assert main(["run", *[str(BIN / "init.ttl"), str(BIN / "goal.ttl")], "--domain", str(ext),
                 "-o", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"{ext}:{_line_of(ext, 'Teleport')}: "), err
    assert "Teleport" in err[0]


def test_an_unknown_target_function_is_refused_at_its_line(tmp_path: Path, capsys) -> None:
    ext = _broken(tmp_path, '"clear(part, 0.08)"', '"hover(part, 0.08)"')
    assert main(["run", str(BIN / "init.ttl"), str(BIN / "goal.ttl"), "--domain", str(ext),
                 "-o", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"{ext}:{_line_of(ext, 'hover(')}: "), err


# --- the docs quote these files -------------------------------------------------------------

def test_the_docs_extension_examples_name_what_the_extension_files_state() -> None:
    """docs/soap.md, "Extending the domain in Turtle": every individual of the test extensions
    it names (xb:..., xp:...) is stated in their files, and each full statement line it quotes
    is in them verbatim, so the worked examples stay those of the tested files."""
    doc = (Path(__file__).resolve().parents[1] / "docs" / "soap.md").read_text()
    section = doc[doc.index("## Extending the domain in Turtle"):]
    files = {"xb": (BIN / "extension.ttl").read_text() + (BIN / "relations.ttl").read_text(),
             "xp": (BUFFER / "extension.ttl").read_text()}
    names = set(re.findall(r"\b(x[bp]):([A-Za-z][\w-]*)", section))
    assert len(names) > 40
    for prefix, local in names:
        assert re.search(rf"^{prefix}:{re.escape(local)} ", files[prefix], re.M), f"{prefix}:{local}"
    quoted = [ln for ln in re.findall(r"^(    soap:has\w+ .+[;.])$", section, re.M) if "..." not in ln]
    assert len(quoted) > 60
    text = re.sub(r"\s+", " ", "\n".join(files.values()))
    pieces = [p.strip() for ln in quoted for p in ln.strip().rstrip(";.").split(" ; ")]
    missing = [p for p in pieces if p not in text]
    assert not missing, missing


def test_a_replan_takes_parts_from_the_bin_too(tmp_path: Path) -> None:
    """A part of the bin dropped in transit (the shipped dropped-part fault, extended to the new
    action by one more statement) is diagnosed by the shipped mode, which replans: the new plan
    takes another part from the bin (the replan's candidates are not parts trays only)."""
    for name in ("init.ttl", "goal.ttl", "relations.ttl"):
        (tmp_path / name).write_text((BIN / name).read_text())
    (tmp_path / "extension.ttl").write_text((BIN / "extension.ttl").read_text() +
                                            "\nkd:fault_dropped-part soap:hasFaultKind_Action xb:take-part-from-bin .\n")
    report = _run(tmp_path, tmp_path, "--faults", "dropped-part@0")
    [failure] = report["failures"]
    assert failure["recovery"] == "replan" and report["replans"] == 1
    taken = [e["args"][1] for e in report["timeline"] if e.get("kind") == "action"
             and e.get("action") == "take-part-from-bin" and e.get("status") == "done"]
    assert taken[0] == "part_b_1" and len(taken) == 2 and taken[1] != "part_b_1"
    assert report["goal_holds"] and report["kits"][0]["score"] == 6


# --- a class of objects the extension declares -----------------------------------------------

def test_an_extension_class_types_objects_for_planning_geometry_and_sensing(tmp_path: Path) -> None:
    """The buffer box is of the extension's class xp:BufferBox: the planner's type of it is the
    model class it descends from, the predicates decided from geometry see it, and a cell served
    with the extension answers a USARTruth query for the class by its local name."""
    import subprocess
    import sys

    from kb.io.loader import domain_knowledge
    from kb.spatial.scene import Scene, class_ancestors

    init = BUFFER / "init.ttl"
    domain_knowledge([BUFFER / "extension.ttl"])  # the domain read, as every command with --domain reads it
    buffer_class = "https://example.org/kitkb-test/buffer-box#BufferBox"
    assert "https://w3id.org/kitkb/kitting#LargeContainer" in class_ancestors()[buffer_class]
    scene = Scene.from_files([init])
    box = next(i for i, n in enumerate(scene.names) if n.endswith("#buffer_box"))
    assert buffer_class in scene.classes[box] and not __import__("numpy").isnan(scene.lo[box]).any()
    server = subprocess.Popen([sys.executable, "-m", "kb.cli", "sim", "serve", str(init), "--domain",
                               str(BUFFER / "extension.ttl"), "--sensor-port", "0", "--command-port", "0"],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        ready = server.stdout.readline()
        port = int(re.search(r"sensor port (\d+)", ready).group(1))
        import socket
        with socket.create_connection(("127.0.0.1", port), timeout=10) as s:
            s.sendall(b"{Class BufferBox}\r\n")
            reader, lines = s.makefile("rb"), []
            while not lines or lines[-1] != "{End}":
                lines.append(reader.readline().decode().rstrip("\r\n"))
        names = [m.group(1) for line in lines if (m := re.search(r"\{Name ([^}]+)\}", line))]
        assert [n.rsplit("#", 1)[-1] for n in names] == ["buffer_box"], lines
        assert "{Class BufferBox}" in lines[0], lines
    finally:
        server.terminate()
        server.wait(timeout=30)


def test_a_world_model_keeps_an_extension_class_s_objects_in_their_model_class(tmp_path: Path, capsys) -> None:
    """``kitkb db load --domain``: the buffer box gets the rows of ktw:LargeContainer (its global
    pose is read back) and keeps its class xp:BufferBox as a type (in the dump)."""
    from kb.world import WorldModel

    db = tmp_path / "w.sqlite"
    assert main(["-q", "db", "load", str(BUFFER / "init.ttl"), "--db", str(db), "--domain",
                 str(BUFFER / "extension.ttl")]) == 0
    with WorldModel(db) as model:
        assert "buffer_box" in model.global_poses()
    assert main(["-q", "db", "dump", "--db", str(db), "-o", str(tmp_path / "d.ttl")]) == 0
    typed = next(line for line in (tmp_path / "d.ttl").read_text().splitlines() if re.match(r"\S*buffer_box a ", line))
    assert "ktw:LargeContainer" in typed and "xp:BufferBox" in typed, typed
