"""Geometry of the workstation: 6-DoF poses as 4x4 transforms and equation (1) of the world
model (:mod:`.transforms`). The 3-D RCC8 relations and cardinal directions the SOAP predicates
are defined by will live here too."""
