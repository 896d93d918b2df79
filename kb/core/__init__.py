"""The ground floor every other room stands on; imports nothing else of kitkb.

``errors`` (the exception root and exit codes), ``diagnostics`` (a problem at ``file:line``),
``namespaces`` (every IRI kitkb spells), ``resources`` (the shipped ontologies and shapes),
``files`` (atomic writes), ``jobs`` (work in a forked child), ``memory`` (garbage-collector
pauses) and ``generators`` (the generator base class and registry).
"""
