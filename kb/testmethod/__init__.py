"""The first paper's four test methods (seed 000 §III) as seeded campaigns on Dask distributed.

``kitkb testmethod basic|new-variety|multi|errors`` runs a campaign: trial ``i`` of a campaign
is a job made from the campaign's method, seed and options alone (:mod:`.methods`): a
workstation whose trays are placed and turned as the trial's seed draws them, a plan made once
per design and worker, an execution in the simulated cell that holds the real placement while
the executor was told the nominal one (:mod:`.trial`). The trials run on a Dask LocalCluster or
cluster and their rows go to a campaign folder that a later run resumes (:mod:`.campaign`);
:mod:`.summary` sums them up. docs/testmethods.md describes each method.
"""

from kb.testmethod.campaign import Campaign, done_rows, run_campaign, trial_path
from kb.testmethod.methods import METHODS, Job, Options, job, jobs, trial_seed
from kb.testmethod.summary import brief, comparable, summarize, write_table

__all__ = ["METHODS", "Campaign", "Job", "Options", "brief", "comparable", "done_rows", "job", "jobs", "run_campaign",
           "summarize", "trial_path", "trial_seed", "write_table"]
