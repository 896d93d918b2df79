"""Plan execution with every action checked from geometry, and the executives' API.

:func:`run_scenario` / :func:`run_plan` carry out a plan on a cell (simulated by default) and
return a :class:`Run` to query (failures by kit, action, predicate, mode and time; the history;
why an action failed). Inside: the executor (:mod:`.executor`), its focus of attention on an
action's neighbourhood (:mod:`.focus`), its recovery from failed checks (:mod:`.recovery`:
diagnosis, retry, rebind, replan, stop), the plan's steps
(:mod:`.steps`), the closed loop that runs it all once over inputs read once (:mod:`.loop`,
:mod:`.inputs`) and its typed events (:mod:`.events`), its belief of the cell (:mod:`.belief`), late-bound CRCL targets
(:mod:`.targets`), the records a run leaves (:mod:`.records`), their one dict form
(:mod:`.codec`) and their store (:mod:`.store`); the cell is opened by URL (:mod:`kb.cells`),
never by importing the simulator.
"""

from kb.execution.api import Run, open_run
from kb.execution.loop import ClosedLoop, LoopOptions, LoopResult, run_plan, run_scenario
from kb.execution.executor import Executor, Stop, log_notifier
from kb.execution.records import FailureRecord, RunRecord

__all__ = ["ClosedLoop", "Executor", "LoopOptions", "LoopResult", "FailureRecord", "Run", "RunRecord", "Stop", "log_notifier", "open_run", "run_plan", "run_scenario"]
