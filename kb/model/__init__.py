"""Typed views of the ontologies that the rest of kitkb reads instead of raw triples.

:class:`kb.model.owl.OwlModel` is an OWL model's classes, restrictions, properties and
datatypes (what validation and the shape derivation read); :mod:`kb.model.soap` is the SOAP
model of actions, predicates and functions (what planning reads).
"""
