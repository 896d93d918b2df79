"""The namespaces kitkb's ontologies live in, and the foreign ones it maps.

Every module takes its IRIs from here so that a namespace is spelled once.
"""

from __future__ import annotations

from rdflib import Namespace

BASE = "https://w3id.org/kitkb/"

#: The kitting workstation model (classes and properties of the IEEE/NIST model).
KTW = Namespace(BASE + "kitting#")
#: The SOAP model: actions, predicates, state relations, RCC8, failures.
SOAP = Namespace(BASE + "soap#")
#: The SOAP instances for kitting: the actions, predicates and failure modes.
KD = Namespace(BASE + "kitting-domain#")
#: Base for scenario data files (one namespace per scenario: SCENARIO + name + "#").
SCENARIO = BASE + "scenario/"

#: Ontology IRIs of the shipped files (what ``owl:imports`` names).
KITTING_ONTOLOGY = BASE + "kitting"
SOAP_ONTOLOGY = BASE + "soap"
KITTING_DOMAIN_ONTOLOGY = BASE + "kitting-domain"

#: The NIST kitting model namespace; the loader maps it onto :data:`KTW`
#: (same local names), so NIST data files are validated against our model.
NIST_KTW = "http://www.nist.gov/el/ontologies/kittingWorkstationClasses.owl#"
#: NIST's SOAP namespace is a different vocabulary from ours and is kept as is.
NIST_SOAP = "http://www.nist.gov/el/ontologies/soapClasses.owl#"
NIST_ONTOLOGY = "http://www.nist.gov/el/ontologies/kittingWorkstationClasses.owl"

#: The W3C SHACL vocabulary.
SH = Namespace("http://www.w3.org/ns/shacl#")

#: Namespace rewrites the loader applies to every term it reads.
NAMESPACE_MAP: dict[str, str] = {NIST_KTW: str(KTW)}

PREFIXES: dict[str, str] = {
    "ktw": str(KTW),
    "soap": str(SOAP),
    "kd": str(KD),
}


def local_name(iri: object) -> str:
    """The local part of an IRI: its fragment if it has one, else its last path segment
    (the whole IRI when that part is empty)."""
    text = str(iri)
    for sep in ("#", "/"):
        if sep in text:
            local = text.rpartition(sep)[2]
            return local or text
    return text
