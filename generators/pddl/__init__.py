"""PDDL from the ontologies, through unified-planning's typed model.

Pipeline (each step one module):

* :mod:`.soap_reader` - SOAP instances (``kitting-domain.ttl``) -> :class:`.spec.DomainSpec`
  (typed ordered parameters, preconditions, add/delete/numeric effects, functions);
* :mod:`.world`, :mod:`.rules`, :mod:`.problem` - initial and goal state files ->
  :class:`.spec.ProblemSpec` (objects, initial facts and values, goal, part quotas);
* :mod:`.strips` - the numeric model compiled to classical STRIPS (counts become tokens);
* :mod:`.build` - specs -> ``unified_planning.model.Problem``;
* :mod:`.writer` - ``PDDLWriter`` output plus ``; source: <IRI>`` comment lines;
* :mod:`.model` - the whole chain for one encoding (``strips`` or ``numeric``).

:mod:`generators.pddl_domain` and :mod:`generators.pddl_problem` are the registered
generators; :mod:`kb.planning` chooses, runs and validates planners.
"""
