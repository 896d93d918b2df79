"""kitkb's SHACL engine: bulk evaluation of SHACL Core and SHACL-SPARQL constraints.

Public entry points are in :mod:`kb.shacl_engine`; this package holds the parts: terms as
N-Triples keys (:mod:`.terms`), the data index (:mod:`.index`), the shape compiler
(:mod:`.shapes`), the core components (:mod:`.constraints`), SPARQL constraints
(:mod:`.sparql`), the pySHACL fallback (:mod:`.fallback`) and the driver (:mod:`.engine`).
"""

from kb.shacl.model import SH, ShaclResult

__all__ = ["SH", "ShaclResult"]
