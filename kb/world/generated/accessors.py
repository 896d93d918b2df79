"""Typed accessors of the kitkb world-model database. GENERATED: do not edit by hand.

Made by generators/accessors.py from https://w3id.org/kitkb/kitting 0.1.0, https://w3id.org/kitkb/soap 0.1.0.
Regenerate: python -m generators.accessors -o kb/world/generated/accessors.py
One class per ontology class (joined-table inheritance); see docs/database.md.
"""

from __future__ import annotations

import datetime

from sqlalchemy import (Boolean, CheckConstraint, Column, Date, DateTime, Float, ForeignKey, Integer,
                        MetaData, Numeric, String, Table, Text, column, literal)
from sqlalchemy.dialects import mysql
from sqlalchemy.orm import DeclarativeBase, Mapped, foreign, mapped_column, relationship, remote

#: Fingerprint of the schema; a database stamped with another one is refused.
SCHEMA_VERSION = 'e41cdb18d01a8ccc'
#: (ontology IRI, owl:versionInfo) of the ontologies the schema was made from.
ONTOLOGIES = (('https://w3id.org/kitkb/kitting', '0.1.0'), ('https://w3id.org/kitkb/soap', '0.1.0'))

_IRI = String(760)
_DECIMAL = Numeric(asdecimal=False).with_variant(mysql.DECIMAL(precision=38, scale=12, asdecimal=False), "mysql")


def _ref(table: str, alter: bool = True) -> ForeignKey:
    """A deferred foreign key to ``table.id`` (checked at commit; cycles are allowed)."""
    return ForeignKey(f"{table}.id", deferrable=True, initially="DEFERRED", use_alter=alter)


class Base(DeclarativeBase):
    """Declarative base of the generated classes."""

    metadata = MetaData(naming_convention={
        "pk": "pk_%(table_name)s",
        "fk": "fk_%(table_name)s_%(column_0_name)s",
        "uq": "uq_%(table_name)s_%(column_0_name)s",
        "ck": "ck_%(table_name)s_%(constraint_name)s",
        "ix": "ix_%(table_name)s_%(column_0_name)s",
    }, info={"version": SCHEMA_VERSION})


# --- kitkb's own tables ---------------------------------------------------------------------

Table("kitkb_meta", Base.metadata, Column("key", String(100), primary_key=True),
      Column("value", Text, nullable=False),
      comment="Version stamp of the schema and other facts about the database.")
Table("kitkb_type", Base.metadata,
      Column("thing_id", Integer, _ref("kitkb_thing"), primary_key=True, autoincrement=False),
      Column("class_iri", _IRI, primary_key=True),
      comment="Asserted types of an individual other than its most specific model class.")
Table("kitkb_literal", Base.metadata,
      Column("thing_id", Integer, _ref("kitkb_thing"), primary_key=True, autoincrement=False),
      Column("property_iri", _IRI, primary_key=True), Column("lexical", Text, nullable=False),
      Column("datatype", _IRI), Column("lang", String(40)),
      comment="Original spelling of literals whose stored value prints differently.")
Table("kitkb_triple", Base.metadata, Column("id", Integer, primary_key=True),
      Column("subject", _IRI, nullable=False, index=True), Column("predicate", _IRI, nullable=False),
      Column("object", Text, nullable=False), Column("object_kind", String(8), nullable=False),
      Column("datatype", _IRI), Column("lang", String(40)),
      CheckConstraint(column("object_kind").in_(["iri", "bnode", "literal"]), name="kind_in"),
      comment="Statements outside the model's tables (ontology header, annotations, foreign terms).")


class Thing(Base):
    """Every individual: its IRI, local name and most specific class."""

    __tablename__ = "kitkb_thing"
    __table_args__ = {"comment": 'Every individual: its IRI, local name and most specific class.', "info": {"iri": "", "parent": ""}}
    __mapper_args__ = {"polymorphic_on": "kind", "polymorphic_identity": ""}

    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    iri: Mapped[str] = mapped_column(_IRI, unique=True)
    name: Mapped[str] = mapped_column(_IRI, index=True)
    kind: Mapped[str] = mapped_column(_IRI, index=True)

ktw_had_by_base_end_effector_changing_station = Table(
    'ktw_had_by_base_end_effector_changing_station', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_mechanical_component'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_end_effector_changing_station'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByBase_EndEffectorChangingStation', 'kind': 'object', 'link': True},
)

ktw_had_by_changing_station_kitting_workstation = Table(
    'ktw_had_by_changing_station_kitting_workstation', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_end_effector_changing_station'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_kitting_workstation'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByChangingStation_KittingWorkstation', 'kind': 'object', 'link': True},
)

ktw_had_by_design_kit = Table(
    'ktw_had_by_design_kit', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_kit_design'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_kit'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByDesign_Kit', 'kind': 'object', 'link': True},
)

ktw_had_by_end_effector_end_effector_holder = Table(
    'ktw_had_by_end_effector_end_effector_holder', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_end_effector'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_end_effector_holder'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByEndEffector_EndEffectorHolder', 'kind': 'object', 'link': True},
)

ktw_had_by_end_effector_holder_end_effector_changing_station = Table(
    'ktw_had_by_end_effector_holder_end_effector_changing_station', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_end_effector_holder'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_end_effector_changing_station'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByEndEffectorHolder_EndEffectorChangingStation', 'kind': 'object', 'link': True},
)

ktw_had_by_end_effector_robot = Table(
    'ktw_had_by_end_effector_robot', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_end_effector'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_robot'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByEndEffector_Robot', 'kind': 'object', 'link': True},
)

ktw_had_by_end_effector_stock_keeping_unit = Table(
    'ktw_had_by_end_effector_stock_keeping_unit', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_end_effector'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_stock_keeping_unit'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByEndEffector_StockKeepingUnit', 'kind': 'object', 'link': True},
)

ktw_had_by_external_shape_no_sku_object = Table(
    'ktw_had_by_external_shape_no_sku_object', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_external_shape'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_no_sku_object'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByExternalShape_NoSkuObject', 'kind': 'object', 'link': True},
)

ktw_had_by_external_shape_stock_keeping_unit = Table(
    'ktw_had_by_external_shape_stock_keeping_unit', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_external_shape'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_stock_keeping_unit'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByExternalShape_StockKeepingUnit', 'kind': 'object', 'link': True},
)

ktw_had_by_grasp_pose_shape_design = Table(
    'ktw_had_by_grasp_pose_shape_design', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_pose_location'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_shape_design'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByGraspPose_ShapeDesign', 'kind': 'object', 'link': True},
)

ktw_had_by_held_object_end_effector = Table(
    'ktw_had_by_held_object_end_effector', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_solid_object'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_end_effector'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByHeldObject_EndEffector', 'kind': 'object', 'link': True},
)

ktw_had_by_internal_shape_no_sku_object = Table(
    'ktw_had_by_internal_shape_no_sku_object', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_internal_shape'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_no_sku_object'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByInternalShape_NoSkuObject', 'kind': 'object', 'link': True},
)

ktw_had_by_internal_shape_stock_keeping_unit = Table(
    'ktw_had_by_internal_shape_stock_keeping_unit', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_internal_shape'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_stock_keeping_unit'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByInternalShape_StockKeepingUnit', 'kind': 'object', 'link': True},
)

ktw_had_by_kit_design_kitting_workstation = Table(
    'ktw_had_by_kit_design_kitting_workstation', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_kit_design'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_kitting_workstation'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByKitDesign_KittingWorkstation', 'kind': 'object', 'link': True},
)

ktw_had_by_kit_design_large_box_with_kits = Table(
    'ktw_had_by_kit_design_large_box_with_kits', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_kit_design'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_large_box_with_kits'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByKitDesign_LargeBoxWithKits', 'kind': 'object', 'link': True},
)

ktw_had_by_kit_large_box_with_kits = Table(
    'ktw_had_by_kit_large_box_with_kits', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_kit'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_large_box_with_kits'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByKit_LargeBoxWithKits', 'kind': 'object', 'link': True},
)

ktw_had_by_kit_tray_kit = Table(
    'ktw_had_by_kit_tray_kit', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_kit_tray'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_kit'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByKitTray_Kit', 'kind': 'object', 'link': True},
)

ktw_had_by_kit_tray_large_box_with_empty_kit_trays = Table(
    'ktw_had_by_kit_tray_large_box_with_empty_kit_trays', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_kit_tray'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_large_box_with_empty_kit_trays'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByKitTray_LargeBoxWithEmptyKitTrays', 'kind': 'object', 'link': True},
)

ktw_had_by_kit_tray_sku_kit_design = Table(
    'ktw_had_by_kit_tray_sku_kit_design', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_stock_keeping_unit'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_kit_design'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByKitTraySku_KitDesign', 'kind': 'object', 'link': True},
)

ktw_had_by_large_container_large_box_with_empty_kit_trays = Table(
    'ktw_had_by_large_container_large_box_with_empty_kit_trays', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_large_container'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_large_box_with_empty_kit_trays'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByLargeContainer_LargeBoxWithEmptyKitTrays', 'kind': 'object', 'link': True},
)

ktw_had_by_large_container_large_box_with_kits = Table(
    'ktw_had_by_large_container_large_box_with_kits', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_large_container'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_large_box_with_kits'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByLargeContainer_LargeBoxWithKits', 'kind': 'object', 'link': True},
)

ktw_had_by_maximum_point_box_volume = Table(
    'ktw_had_by_maximum_point_box_volume', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_point'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_box_volume'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByMaximumPoint_BoxVolume', 'kind': 'object', 'link': True},
)

ktw_had_by_minimum_point_box_volume = Table(
    'ktw_had_by_minimum_point_box_volume', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_point'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_box_volume'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByMinimumPoint_BoxVolume', 'kind': 'object', 'link': True},
)

ktw_had_by_object_kitting_workstation = Table(
    'ktw_had_by_object_kitting_workstation', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_solid_object'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_kitting_workstation'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByObject_KittingWorkstation', 'kind': 'object', 'link': True},
)

ktw_had_by_object_on_table_work_table = Table(
    'ktw_had_by_object_on_table_work_table', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_solid_object'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_work_table'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByObjectOnTable_WorkTable', 'kind': 'object', 'link': True},
)

ktw_had_by_other_obstacle_kitting_workstation = Table(
    'ktw_had_by_other_obstacle_kitting_workstation', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_box_volume'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_kitting_workstation'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByOtherObstacle_KittingWorkstation', 'kind': 'object', 'link': True},
)

ktw_had_by_part_kit = Table(
    'ktw_had_by_part_kit', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_part'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_kit'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByPart_Kit', 'kind': 'object', 'link': True},
)

ktw_had_by_part_parts_vessel = Table(
    'ktw_had_by_part_parts_vessel', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_part'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_parts_vessel'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByPart_PartsVessel', 'kind': 'object', 'link': True},
)

ktw_had_by_part_ref_and_pose_kit_design = Table(
    'ktw_had_by_part_ref_and_pose_kit_design', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_part_ref_and_pose'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_kit_design'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByPartRefAndPose_KitDesign', 'kind': 'object', 'link': True},
)

ktw_had_by_part_ref_and_pose_slot = Table(
    'ktw_had_by_part_ref_and_pose_slot', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_part_ref_and_pose'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_slot'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByPartRefAndPose_Slot', 'kind': 'object', 'link': True},
)

ktw_had_by_part_sku_parts_vessel = Table(
    'ktw_had_by_part_sku_parts_vessel', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_stock_keeping_unit'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_parts_vessel'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByPartSku_PartsVessel', 'kind': 'object', 'link': True},
)

ktw_had_by_part_slot = Table(
    'ktw_had_by_part_slot', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_part'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_slot'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByPart_Slot', 'kind': 'object', 'link': True},
)

ktw_had_by_point_part_ref_and_pose = Table(
    'ktw_had_by_point_part_ref_and_pose', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_point'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_part_ref_and_pose'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByPoint_PartRefAndPose', 'kind': 'object', 'link': True},
)

ktw_had_by_point_pose_location = Table(
    'ktw_had_by_point_pose_location', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_point'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_pose_location'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByPoint_PoseLocation', 'kind': 'object', 'link': True},
)

ktw_had_by_primary_location_solid_object = Table(
    'ktw_had_by_primary_location_solid_object', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_physical_location'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_solid_object'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByPrimaryLocation_SolidObject', 'kind': 'object', 'link': True},
)

ktw_had_by_ref_object_physical_location = Table(
    'ktw_had_by_ref_object_physical_location', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_solid_object'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_physical_location'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByRefObject_PhysicalLocation', 'kind': 'object', 'link': True},
)

ktw_had_by_robot_kitting_workstation = Table(
    'ktw_had_by_robot_kitting_workstation', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_robot'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_kitting_workstation'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByRobot_KittingWorkstation', 'kind': 'object', 'link': True},
)

ktw_had_by_secondary_location_solid_object = Table(
    'ktw_had_by_secondary_location_solid_object', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_physical_location'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_solid_object'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadBySecondaryLocation_SolidObject', 'kind': 'object', 'link': True},
)

ktw_had_by_sensor_kitting_workstation = Table(
    'ktw_had_by_sensor_kitting_workstation', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_pose_sensor'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_kitting_workstation'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadBySensor_KittingWorkstation', 'kind': 'object', 'link': True},
)

ktw_had_by_sku_kitting_workstation = Table(
    'ktw_had_by_sku_kitting_workstation', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_stock_keeping_unit'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_kitting_workstation'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadBySku_KittingWorkstation', 'kind': 'object', 'link': True},
)

ktw_had_by_sku_part_ref_and_pose = Table(
    'ktw_had_by_sku_part_ref_and_pose', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_stock_keeping_unit'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_part_ref_and_pose'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadBySku_PartRefAndPose', 'kind': 'object', 'link': True},
)

ktw_had_by_sku_sku_object = Table(
    'ktw_had_by_sku_sku_object', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_stock_keeping_unit'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_sku_object'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadBySku_SkuObject', 'kind': 'object', 'link': True},
)

ktw_had_by_slot_kit = Table(
    'ktw_had_by_slot_kit', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_slot'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_kit'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadBySlot_Kit', 'kind': 'object', 'link': True},
)

ktw_had_by_work_volume_robot = Table(
    'ktw_had_by_work_volume_robot', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_box_volume'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_robot'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByWorkVolume_Robot', 'kind': 'object', 'link': True},
)

ktw_had_by_x_axis_part_ref_and_pose = Table(
    'ktw_had_by_x_axis_part_ref_and_pose', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_vector'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_part_ref_and_pose'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByXAxis_PartRefAndPose', 'kind': 'object', 'link': True},
)

ktw_had_by_x_axis_pose_location = Table(
    'ktw_had_by_x_axis_pose_location', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_vector'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_pose_location'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByXAxis_PoseLocation', 'kind': 'object', 'link': True},
)

ktw_had_by_z_axis_part_ref_and_pose = Table(
    'ktw_had_by_z_axis_part_ref_and_pose', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_vector'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_part_ref_and_pose'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByZAxis_PartRefAndPose', 'kind': 'object', 'link': True},
)

ktw_had_by_z_axis_pose_location = Table(
    'ktw_had_by_z_axis_pose_location', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_vector'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_pose_location'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hadByZAxis_PoseLocation', 'kind': 'object', 'link': True},
)

ktw_has_end_effector_changing_station_end_effector_holder = Table(
    'ktw_has_end_effector_changing_station_end_effector_holder', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_end_effector_changing_station'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_end_effector_holder'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hasEndEffectorChangingStation_EndEffectorHolder', 'kind': 'object', 'link': True},
)

ktw_has_kit_design_part_ref_and_pose = Table(
    'ktw_has_kit_design_part_ref_and_pose', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_kit_design'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_part_ref_and_pose'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hasKitDesign_PartRefAndPose', 'kind': 'object', 'link': True},
)

ktw_has_kit_part = Table(
    'ktw_has_kit_part', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_kit'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_part'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hasKit_Part', 'kind': 'object', 'link': True},
)

ktw_has_kit_slot = Table(
    'ktw_has_kit_slot', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_kit'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_slot'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hasKit_Slot', 'kind': 'object', 'link': True},
)

ktw_has_kitting_workstation_kit_design = Table(
    'ktw_has_kitting_workstation_kit_design', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_kitting_workstation'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_kit_design'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hasKittingWorkstation_KitDesign', 'kind': 'object', 'link': True},
)

ktw_has_kitting_workstation_object = Table(
    'ktw_has_kitting_workstation_object', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_kitting_workstation'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_solid_object'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hasKittingWorkstation_Object', 'kind': 'object', 'link': True},
)

ktw_has_kitting_workstation_other_obstacle = Table(
    'ktw_has_kitting_workstation_other_obstacle', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_kitting_workstation'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_box_volume'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hasKittingWorkstation_OtherObstacle', 'kind': 'object', 'link': True},
)

ktw_has_kitting_workstation_sku = Table(
    'ktw_has_kitting_workstation_sku', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_kitting_workstation'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_stock_keeping_unit'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hasKittingWorkstation_Sku', 'kind': 'object', 'link': True},
)

ktw_has_large_box_with_empty_kit_trays_kit_tray = Table(
    'ktw_has_large_box_with_empty_kit_trays_kit_tray', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_large_box_with_empty_kit_trays'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_kit_tray'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hasLargeBoxWithEmptyKitTrays_KitTray', 'kind': 'object', 'link': True},
)

ktw_has_large_box_with_kits_kit = Table(
    'ktw_has_large_box_with_kits_kit', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_large_box_with_kits'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_kit'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hasLargeBoxWithKits_Kit', 'kind': 'object', 'link': True},
)

ktw_has_parts_vessel_part = Table(
    'ktw_has_parts_vessel_part', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_parts_vessel'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_part'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hasPartsVessel_Part', 'kind': 'object', 'link': True},
)

ktw_has_robot_work_volume = Table(
    'ktw_has_robot_work_volume', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_robot'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_box_volume'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hasRobot_WorkVolume', 'kind': 'object', 'link': True},
)

ktw_has_solid_object_secondary_location = Table(
    'ktw_has_solid_object_secondary_location', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_solid_object'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_physical_location'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hasSolidObject_SecondaryLocation', 'kind': 'object', 'link': True},
)

ktw_has_stock_keeping_unit_end_effector = Table(
    'ktw_has_stock_keeping_unit_end_effector', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_stock_keeping_unit'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_end_effector'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hasStockKeepingUnit_EndEffector', 'kind': 'object', 'link': True},
)

ktw_has_work_table_object_on_table = Table(
    'ktw_has_work_table_object_on_table', Base.metadata,
    Column("subject_id", Integer, _ref('ktw_work_table'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('ktw_solid_object'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/kitting#hasWorkTable_ObjectOnTable', 'kind': 'object', 'link': True},
)

soap_has_action_failure_violated_atom = Table(
    'soap_has_action_failure_violated_atom', Base.metadata,
    Column("subject_id", Integer, _ref('soap_action_failure'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('soap_predicate_atom'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/soap#hasActionFailure_ViolatedAtom', 'kind': 'object', 'link': True},
)

soap_has_action_parameter = Table(
    'soap_has_action_parameter', Base.metadata,
    Column("subject_id", Integer, _ref('soap_action'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('soap_parameter'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/soap#hasAction_Parameter', 'kind': 'object', 'link': True},
)

soap_has_action_program_step = Table(
    'soap_has_action_program_step', Base.metadata,
    Column("subject_id", Integer, _ref('soap_action_program'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('soap_command_step'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/soap#hasActionProgram_Step', 'kind': 'object', 'link': True},
)

soap_has_conjunction_operand = Table(
    'soap_has_conjunction_operand', Base.metadata,
    Column("subject_id", Integer, _ref('soap_conjunction'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('soap_formula'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/soap#hasConjunction_Operand', 'kind': 'object', 'link': True},
)

soap_has_disjunction_operand = Table(
    'soap_has_disjunction_operand', Base.metadata,
    Column("subject_id", Integer, _ref('soap_disjunction'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('soap_formula'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/soap#hasDisjunction_Operand', 'kind': 'object', 'link': True},
)

soap_has_effect_numeric_effect = Table(
    'soap_has_effect_numeric_effect', Base.metadata,
    Column("subject_id", Integer, _ref('soap_effect'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('soap_numeric_effect'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/soap#hasEffect_NumericEffect', 'kind': 'object', 'link': True},
)

soap_has_effect_predicate_atom = Table(
    'soap_has_effect_predicate_atom', Base.metadata,
    Column("subject_id", Integer, _ref('soap_effect'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('soap_predicate_atom'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/soap#hasEffect_PredicateAtom', 'kind': 'object', 'link': True},
)

soap_has_failure_mode_consequence_atom = Table(
    'soap_has_failure_mode_consequence_atom', Base.metadata,
    Column("subject_id", Integer, _ref('soap_failure_mode'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('soap_predicate_atom'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/soap#hasFailureMode_ConsequenceAtom', 'kind': 'object', 'link': True},
)

soap_has_failure_mode_object_consequence = Table(
    'soap_has_failure_mode_object_consequence', Base.metadata,
    Column("subject_id", Integer, _ref('soap_failure_mode'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('soap_object_consequence'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/soap#hasFailureMode_ObjectConsequence', 'kind': 'object', 'link': True},
)

soap_has_failure_mode_violated_predicate = Table(
    'soap_has_failure_mode_violated_predicate', Base.metadata,
    Column("subject_id", Integer, _ref('soap_failure_mode'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('soap_predicate'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/soap#hasFailureMode_ViolatedPredicate', 'kind': 'object', 'link': True},
)

soap_has_failure_remediation_notification = Table(
    'soap_has_failure_remediation_notification', Base.metadata,
    Column("subject_id", Integer, _ref('soap_failure_remediation'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('soap_notification'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/soap#hasFailureRemediation_Notification', 'kind': 'object', 'link': True},
)

soap_has_fault_kind_action = Table(
    'soap_has_fault_kind_action', Base.metadata,
    Column("subject_id", Integer, _ref('soap_fault_kind'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('soap_action'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/soap#hasFaultKind_Action', 'kind': 'object', 'link': True},
)

soap_has_fault_kind_also_names = Table(
    'soap_has_fault_kind_also_names', Base.metadata,
    Column("subject_id", Integer, _ref('soap_fault_kind'), primary_key=True, autoincrement=False),
    Column("value", _IRI, primary_key=True, autoincrement=False),
    info={'iri': 'https://w3id.org/kitkb/soap#hasFaultKind_AlsoNames', 'kind': 'iri', 'link': True},
)

soap_has_fault_kind_diagnosed_by = Table(
    'soap_has_fault_kind_diagnosed_by', Base.metadata,
    Column("subject_id", Integer, _ref('soap_fault_kind'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('soap_failure_mode'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/soap#hasFaultKind_DiagnosedBy', 'kind': 'object', 'link': True},
)

soap_has_fault_kind_target = Table(
    'soap_has_fault_kind_target', Base.metadata,
    Column("subject_id", Integer, _ref('soap_fault_kind'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('soap_parameter'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/soap#hasFaultKind_Target', 'kind': 'object', 'link': True},
)

soap_has_precondition_function_comparison = Table(
    'soap_has_precondition_function_comparison', Base.metadata,
    Column("subject_id", Integer, _ref('soap_precondition'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('soap_function_comparison'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/soap#hasPrecondition_FunctionComparison', 'kind': 'object', 'link': True},
)

soap_has_precondition_predicate_atom = Table(
    'soap_has_precondition_predicate_atom', Base.metadata,
    Column("subject_id", Integer, _ref('soap_precondition'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('soap_predicate_atom'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/soap#hasPrecondition_PredicateAtom', 'kind': 'object', 'link': True},
)

soap_has_recovery_plan_step = Table(
    'soap_has_recovery_plan_step', Base.metadata,
    Column("subject_id", Integer, _ref('soap_recovery_plan'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('soap_recovery_step'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/soap#hasRecoveryPlan_Step', 'kind': 'object', 'link': True},
)

soap_has_recovery_step_binding = Table(
    'soap_has_recovery_step_binding', Base.metadata,
    Column("subject_id", Integer, _ref('soap_recovery_step'), primary_key=True, autoincrement=False),
    Column("value_id", Integer, _ref('soap_parameter_binding'), primary_key=True),
    info={'iri': 'https://w3id.org/kitkb/soap#hasRecoveryStep_Binding', 'kind': 'object', 'link': True},
)


class DataThing(Thing):
    """Root of the data-valued classes (points, vectors, locations, designs, shapes, SKUs). Disjoint from SolidObject. Abstract: instantiate a subclass.

    Class <https://w3id.org/kitkb/kitting#DataThing>.
    """

    __tablename__ = 'ktw_data_thing'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#DataThing', 'parent': 'kitkb_thing'}, 'comment': 'Root of the data-valued classes (points, vectors, locations, designs, shapes, SKUs). Disjoint from SolidObject. Abstract: instantiate a subclass.'}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#DataThing', "inherit_condition": id.column == Thing.__table__.c.id}


class SolidObject(Thing):
    """Root of everything in the cell that has extent in space. Abstract: instantiate a subclass. Each solid object has one primary location; every chain of primary locations ends at the kitting workstation, the only object allowed to be located relative to itself.

    Class <https://w3id.org/kitkb/kitting#SolidObject>.
    """

    __tablename__ = 'ktw_solid_object'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#SolidObject', 'parent': 'kitkb_thing'}, 'comment': 'Root of everything in the cell that has extent in space. Abstract: instantiate a subclass. Each solid object has one primary location; every chain of primary locations ends at the kitting workstation, the only object allowed to be located relative to itself.'}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#SolidObject', "inherit_condition": id.column == Thing.__table__.c.id}
    primary_location_id: Mapped[int] = mapped_column(Integer, _ref('ktw_physical_location'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasSolidObject_PrimaryLocation', 'kind': 'object'})
    primary_location: Mapped[PhysicalLocation] = relationship('PhysicalLocation', primaryjoin=lambda: foreign(SolidObject.__table__.c.primary_location_id) == remote(PhysicalLocation.__table__.c.id), foreign_keys=lambda: [SolidObject.__table__.c.primary_location_id])
    had_by_held_object_end_effector: Mapped[list[EndEffector]] = relationship('EndEffector', secondary=lambda: ktw_had_by_held_object_end_effector, primaryjoin=lambda: SolidObject.__table__.c.id == ktw_had_by_held_object_end_effector.c.subject_id, secondaryjoin=lambda: EndEffector.__table__.c.id == ktw_had_by_held_object_end_effector.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByHeldObject_EndEffector'})
    had_by_object_kitting_workstation: Mapped[list[KittingWorkstation]] = relationship('KittingWorkstation', secondary=lambda: ktw_had_by_object_kitting_workstation, primaryjoin=lambda: SolidObject.__table__.c.id == ktw_had_by_object_kitting_workstation.c.subject_id, secondaryjoin=lambda: KittingWorkstation.__table__.c.id == ktw_had_by_object_kitting_workstation.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByObject_KittingWorkstation'})
    had_by_object_on_table_work_table: Mapped[list[WorkTable]] = relationship('WorkTable', secondary=lambda: ktw_had_by_object_on_table_work_table, primaryjoin=lambda: SolidObject.__table__.c.id == ktw_had_by_object_on_table_work_table.c.subject_id, secondaryjoin=lambda: WorkTable.__table__.c.id == ktw_had_by_object_on_table_work_table.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByObjectOnTable_WorkTable'})
    had_by_ref_object_physical_location: Mapped[list[PhysicalLocation]] = relationship('PhysicalLocation', secondary=lambda: ktw_had_by_ref_object_physical_location, primaryjoin=lambda: SolidObject.__table__.c.id == ktw_had_by_ref_object_physical_location.c.subject_id, secondaryjoin=lambda: PhysicalLocation.__table__.c.id == ktw_had_by_ref_object_physical_location.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByRefObject_PhysicalLocation'})
    secondary_location: Mapped[list[PhysicalLocation]] = relationship('PhysicalLocation', secondary=lambda: ktw_has_solid_object_secondary_location, primaryjoin=lambda: SolidObject.__table__.c.id == ktw_has_solid_object_secondary_location.c.subject_id, secondaryjoin=lambda: PhysicalLocation.__table__.c.id == ktw_has_solid_object_secondary_location.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hasSolidObject_SecondaryLocation'})


class Action(Thing):
    """An operator a planner may put in a plan. It has a unique name, an ordered list of typed parameters, one precondition and one effect.

    Class <https://w3id.org/kitkb/soap#Action>.
    """

    __tablename__ = 'soap_action'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Action', 'parent': 'kitkb_thing'}, 'comment': 'An operator a planner may put in a plan. It has a unique name, an ordered list of typed parameters, one precondition and one effect.'}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Action', "inherit_condition": id.column == Thing.__table__.c.id}
    effect_id: Mapped[int] = mapped_column(Integer, _ref('soap_effect'), unique=True, info={'iri': 'https://w3id.org/kitkb/soap#hasAction_Effect', 'kind': 'object'})
    effect: Mapped[Effect] = relationship('Effect', primaryjoin=lambda: foreign(Action.__table__.c.effect_id) == remote(Effect.__table__.c.id), foreign_keys=lambda: [Action.__table__.c.effect_id])
    first_parameter_id: Mapped[int | None] = mapped_column(Integer, _ref('soap_parameter'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasAction_FirstParameter', 'kind': 'object'})
    first_parameter: Mapped[Parameter | None] = relationship('Parameter', primaryjoin=lambda: foreign(Action.__table__.c.first_parameter_id) == remote(Parameter.__table__.c.id), foreign_keys=lambda: [Action.__table__.c.first_parameter_id])
    action_name: Mapped[str] = mapped_column('name', Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasAction_Name', 'kind': 'data', 'value': 'text'})
    precondition_id: Mapped[int] = mapped_column(Integer, _ref('soap_precondition'), unique=True, info={'iri': 'https://w3id.org/kitkb/soap#hasAction_Precondition', 'kind': 'object'})
    precondition: Mapped[Precondition] = relationship('Precondition', primaryjoin=lambda: foreign(Action.__table__.c.precondition_id) == remote(Precondition.__table__.c.id), foreign_keys=lambda: [Action.__table__.c.precondition_id])
    parameter: Mapped[list[Parameter]] = relationship('Parameter', secondary=lambda: soap_has_action_parameter, primaryjoin=lambda: Action.__table__.c.id == soap_has_action_parameter.c.subject_id, secondaryjoin=lambda: Parameter.__table__.c.id == soap_has_action_parameter.c.value_id, info={'iri': 'https://w3id.org/kitkb/soap#hasAction_Parameter'})


class ActionFailure(Thing):
    """A detected failure of one executed action (a run-time record): the action, the phase, the predicate atoms found violated, and the failure mode diagnosed.

    Class <https://w3id.org/kitkb/soap#ActionFailure>.
    """

    __tablename__ = 'soap_action_failure'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#ActionFailure', 'parent': 'kitkb_thing'}, 'comment': 'A detected failure of one executed action (a run-time record): the action, the phase, the predicate atoms found violated, and the failure mode diagnosed.'}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#ActionFailure', "inherit_condition": id.column == Thing.__table__.c.id}
    action_id: Mapped[int] = mapped_column(Integer, _ref('soap_action'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasActionFailure_Action', 'kind': 'object'})
    action: Mapped[Action] = relationship('Action', primaryjoin=lambda: foreign(ActionFailure.__table__.c.action_id) == remote(Action.__table__.c.id), foreign_keys=lambda: [ActionFailure.__table__.c.action_id])
    failure_mode_id: Mapped[int | None] = mapped_column(Integer, _ref('soap_failure_mode'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasActionFailure_FailureMode', 'kind': 'object'})
    failure_mode: Mapped[FailureMode | None] = relationship('FailureMode', primaryjoin=lambda: foreign(ActionFailure.__table__.c.failure_mode_id) == remote(FailureMode.__table__.c.id), foreign_keys=lambda: [ActionFailure.__table__.c.failure_mode_id])
    phase_id: Mapped[int] = mapped_column(Integer, _ref('soap_check_phase'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasActionFailure_Phase', 'kind': 'object'})
    phase: Mapped[CheckPhase] = relationship('CheckPhase', primaryjoin=lambda: foreign(ActionFailure.__table__.c.phase_id) == remote(CheckPhase.__table__.c.id), foreign_keys=lambda: [ActionFailure.__table__.c.phase_id])
    timestamp: Mapped[datetime.datetime | None] = mapped_column(DateTime(timezone=True), nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasActionFailure_Timestamp', 'kind': 'data', 'value': 'datetime', 'datatype': 'http://www.w3.org/2001/XMLSchema#dateTime'})
    violated_atom: Mapped[list[PredicateAtom]] = relationship('PredicateAtom', secondary=lambda: soap_has_action_failure_violated_atom, primaryjoin=lambda: ActionFailure.__table__.c.id == soap_has_action_failure_violated_atom.c.subject_id, secondaryjoin=lambda: PredicateAtom.__table__.c.id == soap_has_action_failure_violated_atom.c.value_id, info={'iri': 'https://w3id.org/kitkb/soap#hasActionFailure_ViolatedAtom'})


class ActionProgram(Thing):
    """The robot commands (CRCL) that carry out one action, as data: each step names a command and, for a motion, a target pose computed at execution time from where the objects really are (late binding). The executor has no Python per action.

    Class <https://w3id.org/kitkb/soap#ActionProgram>.
    """

    __tablename__ = 'soap_action_program'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#ActionProgram', 'parent': 'kitkb_thing'}, 'comment': 'The robot commands (CRCL) that carry out one action, as data: each step names a command and, for a motion, a target pose computed at execution time from where the objects really are (late binding). The executor has no Python per action.'}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#ActionProgram', "inherit_condition": id.column == Thing.__table__.c.id}
    action_id: Mapped[int] = mapped_column(Integer, _ref('soap_action'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasActionProgram_Action', 'kind': 'object'})
    action: Mapped[Action] = relationship('Action', primaryjoin=lambda: foreign(ActionProgram.__table__.c.action_id) == remote(Action.__table__.c.id), foreign_keys=lambda: [ActionProgram.__table__.c.action_id])
    step: Mapped[list[CommandStep]] = relationship('CommandStep', secondary=lambda: soap_has_action_program_step, primaryjoin=lambda: ActionProgram.__table__.c.id == soap_has_action_program_step.c.subject_id, secondaryjoin=lambda: CommandStep.__table__.c.id == soap_has_action_program_step.c.value_id, info={'iri': 'https://w3id.org/kitkb/soap#hasActionProgram_Step'})


class CheckPhase(Thing):
    """When a predicate check detects a failure: before the action (its precondition) or after it (its effect). Its two individuals are soap:PreconditionCheck and soap:EffectCheck (not closed with owl:oneOf, which would slow reasoning with nominals).

    Class <https://w3id.org/kitkb/soap#CheckPhase>.
    """

    __tablename__ = 'soap_check_phase'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#CheckPhase', 'parent': 'kitkb_thing'}, 'comment': 'When a predicate check detects a failure: before the action (its precondition) or after it (its effect). Its two individuals are soap:PreconditionCheck and soap:EffectCheck (not closed with owl:oneOf, which would slow reasoning with nominals).'}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#CheckPhase', "inherit_condition": id.column == Thing.__table__.c.id}


class CommandStep(Thing):
    """One CRCL command of an action program: the command name (as CRCL.xsd names its element: MoveTo, CloseGripper, Dwell, Message, ...), and its argument: a target pose expression for a motion, a duration for Dwell, a text with {parameter} placeholders for Message.

    Class <https://w3id.org/kitkb/soap#CommandStep>.
    """

    __tablename__ = 'soap_command_step'
    __table_args__ = (
        CheckConstraint(column('position') > literal(0), name='position_gt_0'),
        {'info': {'iri': 'https://w3id.org/kitkb/soap#CommandStep', 'parent': 'kitkb_thing'}, 'comment': 'One CRCL command of an action program: the command name (as CRCL.xsd names its element: MoveTo, CloseGripper, Dwell, Message, ...), and its argument: a target pose expression for a motion, a duration for Dwell, a text with {parameter} placeholders for Message.'},
    )

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#CommandStep', "inherit_condition": id.column == Thing.__table__.c.id}
    approach: Mapped[bool | None] = mapped_column(Boolean(), nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasCommandStep_Approach', 'kind': 'data', 'value': 'boolean', 'datatype': 'http://www.w3.org/2001/XMLSchema#boolean'})
    command: Mapped[str] = mapped_column(Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasCommandStep_Command', 'kind': 'data', 'value': 'text'})
    duration: Mapped[float | None] = mapped_column(_DECIMAL, nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasCommandStep_Duration', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    position: Mapped[int] = mapped_column(Integer(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasCommandStep_Position', 'kind': 'data', 'value': 'integer', 'datatype': 'http://www.w3.org/2001/XMLSchema#positiveInteger'})
    target: Mapped[str | None] = mapped_column(Text(), nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasCommandStep_Target', 'kind': 'data', 'value': 'text'})
    text: Mapped[str | None] = mapped_column(Text(), nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasCommandStep_Text', 'kind': 'data', 'value': 'text'})


class ConsequenceKind(Thing):
    """What a failure implies about an object; the individuals are soap:Condemned, soap:Missing, soap:ReusableAfterInspection and soap:Moved.

    Class <https://w3id.org/kitkb/soap#ConsequenceKind>.
    """

    __tablename__ = 'soap_consequence_kind'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#ConsequenceKind', 'parent': 'kitkb_thing'}, 'comment': 'What a failure implies about an object; the individuals are soap:Condemned, soap:Missing, soap:ReusableAfterInspection and soap:Moved.'}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#ConsequenceKind', "inherit_condition": id.column == Thing.__table__.c.id}


class Effect(Thing):
    """What an action changes: predicate atoms it makes true (add) or, when negated, false (delete), and numeric updates of functions.

    Class <https://w3id.org/kitkb/soap#Effect>.
    """

    __tablename__ = 'soap_effect'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Effect', 'parent': 'kitkb_thing'}, 'comment': 'What an action changes: predicate atoms it makes true (add) or, when negated, false (delete), and numeric updates of functions.'}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Effect', "inherit_condition": id.column == Thing.__table__.c.id}
    numeric_effect: Mapped[list[NumericEffect]] = relationship('NumericEffect', secondary=lambda: soap_has_effect_numeric_effect, primaryjoin=lambda: Effect.__table__.c.id == soap_has_effect_numeric_effect.c.subject_id, secondaryjoin=lambda: NumericEffect.__table__.c.id == soap_has_effect_numeric_effect.c.value_id, info={'iri': 'https://w3id.org/kitkb/soap#hasEffect_NumericEffect'})
    predicate_atom: Mapped[list[PredicateAtom]] = relationship('PredicateAtom', secondary=lambda: soap_has_effect_predicate_atom, primaryjoin=lambda: Effect.__table__.c.id == soap_has_effect_predicate_atom.c.subject_id, secondaryjoin=lambda: PredicateAtom.__table__.c.id == soap_has_effect_predicate_atom.c.value_id, info={'iri': 'https://w3id.org/kitkb/soap#hasEffect_PredicateAtom'})


class ExecutionPolicy(Thing):
    """How a domain's executor decides what the failure model leaves open: what it does with a kit it cannot finish (one policy per domain).

    Class <https://w3id.org/kitkb/soap#ExecutionPolicy>.
    """

    __tablename__ = 'soap_execution_policy'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#ExecutionPolicy', 'parent': 'kitkb_thing'}, 'comment': "How a domain's executor decides what the failure model leaves open: what it does with a kit it cannot finish (one policy per domain)."}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#ExecutionPolicy', "inherit_condition": id.column == Thing.__table__.c.id}
    partial_kits_id: Mapped[int | None] = mapped_column(Integer, _ref('soap_partial_kit_policy'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasExecutionPolicy_PartialKits', 'kind': 'object'})
    partial_kits: Mapped[PartialKitPolicy | None] = relationship('PartialKitPolicy', primaryjoin=lambda: foreign(ExecutionPolicy.__table__.c.partial_kits_id) == remote(PartialKitPolicy.__table__.c.id), foreign_keys=lambda: [ExecutionPolicy.__table__.c.partial_kits_id])


class FailureMode(Thing):
    """A known way an action can fail: the action and check phase it belongs to, the predicates whose violation signals it, a discriminating condition that tells it apart from other modes signalled by the same predicates (evaluated after the failure, with the action's parameters bound), its consequence, severity, likelihood and remediation.

    Class <https://w3id.org/kitkb/soap#FailureMode>.
    """

    __tablename__ = 'soap_failure_mode'
    __table_args__ = (
        CheckConstraint(column('likelihood') >= literal(0.0), name='likelihood_ge_0_0'),
        CheckConstraint(column('likelihood') <= literal(1.0), name='likelihood_le_1_0'),
        CheckConstraint(column('severity') >= literal(1), name='severity_ge_1'),
        CheckConstraint(column('severity') <= literal(10), name='severity_le_10'),
        {'info': {'iri': 'https://w3id.org/kitkb/soap#FailureMode', 'parent': 'kitkb_thing'}, 'comment': "A known way an action can fail: the action and check phase it belongs to, the predicates whose violation signals it, a discriminating condition that tells it apart from other modes signalled by the same predicates (evaluated after the failure, with the action's parameters bound), its consequence, severity, likelihood and remediation."},
    )

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#FailureMode', "inherit_condition": id.column == Thing.__table__.c.id}
    action_id: Mapped[int] = mapped_column(Integer, _ref('soap_action'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFailureMode_Action', 'kind': 'object'})
    action: Mapped[Action] = relationship('Action', primaryjoin=lambda: foreign(FailureMode.__table__.c.action_id) == remote(Action.__table__.c.id), foreign_keys=lambda: [FailureMode.__table__.c.action_id])
    condition_id: Mapped[int | None] = mapped_column(Integer, _ref('soap_formula'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFailureMode_Condition', 'kind': 'object'})
    condition: Mapped[Formula | None] = relationship('Formula', primaryjoin=lambda: foreign(FailureMode.__table__.c.condition_id) == remote(Formula.__table__.c.id), foreign_keys=lambda: [FailureMode.__table__.c.condition_id])
    consequence: Mapped[str] = mapped_column(Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasFailureMode_Consequence', 'kind': 'data', 'value': 'text'})
    likelihood: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasFailureMode_Likelihood', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    failure_mode_name: Mapped[str] = mapped_column('name', Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasFailureMode_Name', 'kind': 'data', 'value': 'text'})
    phase_id: Mapped[int] = mapped_column(Integer, _ref('soap_check_phase'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFailureMode_Phase', 'kind': 'object'})
    phase: Mapped[CheckPhase] = relationship('CheckPhase', primaryjoin=lambda: foreign(FailureMode.__table__.c.phase_id) == remote(CheckPhase.__table__.c.id), foreign_keys=lambda: [FailureMode.__table__.c.phase_id])
    remediation_id: Mapped[int] = mapped_column(Integer, _ref('soap_failure_remediation'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFailureMode_Remediation', 'kind': 'object'})
    remediation: Mapped[FailureRemediation] = relationship('FailureRemediation', primaryjoin=lambda: foreign(FailureMode.__table__.c.remediation_id) == remote(FailureRemediation.__table__.c.id), foreign_keys=lambda: [FailureMode.__table__.c.remediation_id])
    severity: Mapped[int] = mapped_column(Integer(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasFailureMode_Severity', 'kind': 'data', 'value': 'integer', 'datatype': 'http://www.w3.org/2001/XMLSchema#integer'})
    consequence_atom: Mapped[list[PredicateAtom]] = relationship('PredicateAtom', secondary=lambda: soap_has_failure_mode_consequence_atom, primaryjoin=lambda: FailureMode.__table__.c.id == soap_has_failure_mode_consequence_atom.c.subject_id, secondaryjoin=lambda: PredicateAtom.__table__.c.id == soap_has_failure_mode_consequence_atom.c.value_id, info={'iri': 'https://w3id.org/kitkb/soap#hasFailureMode_ConsequenceAtom'})
    object_consequence: Mapped[list[ObjectConsequence]] = relationship('ObjectConsequence', secondary=lambda: soap_has_failure_mode_object_consequence, primaryjoin=lambda: FailureMode.__table__.c.id == soap_has_failure_mode_object_consequence.c.subject_id, secondaryjoin=lambda: ObjectConsequence.__table__.c.id == soap_has_failure_mode_object_consequence.c.value_id, info={'iri': 'https://w3id.org/kitkb/soap#hasFailureMode_ObjectConsequence'})
    violated_predicate: Mapped[list[Predicate]] = relationship('Predicate', secondary=lambda: soap_has_failure_mode_violated_predicate, primaryjoin=lambda: FailureMode.__table__.c.id == soap_has_failure_mode_violated_predicate.c.subject_id, secondaryjoin=lambda: Predicate.__table__.c.id == soap_has_failure_mode_violated_predicate.c.value_id, info={'iri': 'https://w3id.org/kitkb/soap#hasFailureMode_ViolatedPredicate'})


class FailureRemediation(Thing):
    """The response to a failure mode: notifications to send, the recovery strategy, an optional recovery plan, and whether an operator must intervene.

    Class <https://w3id.org/kitkb/soap#FailureRemediation>.
    """

    __tablename__ = 'soap_failure_remediation'
    __table_args__ = (
        CheckConstraint(column('max_retries') >= literal(0), name='max_retries_ge_0'),
        {'info': {'iri': 'https://w3id.org/kitkb/soap#FailureRemediation', 'parent': 'kitkb_thing'}, 'comment': 'The response to a failure mode: notifications to send, the recovery strategy, an optional recovery plan, and whether an operator must intervene.'},
    )

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#FailureRemediation', "inherit_condition": id.column == Thing.__table__.c.id}
    max_retries: Mapped[int | None] = mapped_column(Integer(), nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFailureRemediation_MaxRetries', 'kind': 'data', 'value': 'integer', 'datatype': 'http://www.w3.org/2001/XMLSchema#nonNegativeInteger'})
    object_id: Mapped[int | None] = mapped_column(Integer, _ref('soap_parameter'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFailureRemediation_Object', 'kind': 'object'})
    object: Mapped[Parameter | None] = relationship('Parameter', primaryjoin=lambda: foreign(FailureRemediation.__table__.c.object_id) == remote(Parameter.__table__.c.id), foreign_keys=lambda: [FailureRemediation.__table__.c.object_id])
    operator_intervention: Mapped[bool] = mapped_column(Boolean(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasFailureRemediation_OperatorIntervention', 'kind': 'data', 'value': 'boolean', 'datatype': 'http://www.w3.org/2001/XMLSchema#boolean'})
    recovery_id: Mapped[int] = mapped_column(Integer, _ref('soap_recovery_strategy'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFailureRemediation_Recovery', 'kind': 'object'})
    recovery: Mapped[RecoveryStrategy] = relationship('RecoveryStrategy', primaryjoin=lambda: foreign(FailureRemediation.__table__.c.recovery_id) == remote(RecoveryStrategy.__table__.c.id), foreign_keys=lambda: [FailureRemediation.__table__.c.recovery_id])
    recovery_plan_id: Mapped[int | None] = mapped_column(Integer, _ref('soap_recovery_plan'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFailureRemediation_RecoveryPlan', 'kind': 'object'})
    recovery_plan: Mapped[RecoveryPlan | None] = relationship('RecoveryPlan', primaryjoin=lambda: foreign(FailureRemediation.__table__.c.recovery_plan_id) == remote(RecoveryPlan.__table__.c.id), foreign_keys=lambda: [FailureRemediation.__table__.c.recovery_plan_id])
    then_replan: Mapped[bool | None] = mapped_column(Boolean(), nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFailureRemediation_ThenReplan', 'kind': 'data', 'value': 'boolean', 'datatype': 'http://www.w3.org/2001/XMLSchema#boolean'})
    notification: Mapped[list[Notification]] = relationship('Notification', secondary=lambda: soap_has_failure_remediation_notification, primaryjoin=lambda: FailureRemediation.__table__.c.id == soap_has_failure_remediation_notification.c.subject_id, secondaryjoin=lambda: Notification.__table__.c.id == soap_has_failure_remediation_notification.c.value_id, info={'iri': 'https://w3id.org/kitkb/soap#hasFailureRemediation_Notification'})


class FaultKind(Thing):
    """A seeded fault a simulated cell can inject: the actions it can strike (and, on each, the parameter naming the object it acts on), the simulator mechanism that carries it out, the failure modes that are a right diagnosis of it, whether every injection must be detected (false: late binding may find the object where it now is, with no failure needed), whether the right diagnosis rejects the object, and its default rate in the errors test method. Its rdfs:comment says what happens, for listings.

    Class <https://w3id.org/kitkb/soap#FaultKind>.
    """

    __tablename__ = 'soap_fault_kind'
    __table_args__ = (
        CheckConstraint(column('position') > literal(0), name='position_gt_0'),
        CheckConstraint(column('test_method_rate') >= literal(0.0), name='test_method_rate_ge_0_0'),
        CheckConstraint(column('test_method_rate') <= literal(1.0), name='test_method_rate_le_1_0'),
        {'info': {'iri': 'https://w3id.org/kitkb/soap#FaultKind', 'parent': 'kitkb_thing'}, 'comment': 'A seeded fault a simulated cell can inject: the actions it can strike (and, on each, the parameter naming the object it acts on), the simulator mechanism that carries it out, the failure modes that are a right diagnosis of it, whether every injection must be detected (false: late binding may find the object where it now is, with no failure needed), whether the right diagnosis rejects the object, and its default rate in the errors test method. Its rdfs:comment says what happens, for listings.'},
    )

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#FaultKind', "inherit_condition": id.column == Thing.__table__.c.id}
    mechanism_id: Mapped[int] = mapped_column(Integer, _ref('soap_fault_mechanism'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFaultKind_Mechanism', 'kind': 'object'})
    mechanism: Mapped[FaultMechanism] = relationship('FaultMechanism', primaryjoin=lambda: foreign(FaultKind.__table__.c.mechanism_id) == remote(FaultMechanism.__table__.c.id), foreign_keys=lambda: [FaultKind.__table__.c.mechanism_id])
    must_be_detected: Mapped[bool] = mapped_column(Boolean(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasFaultKind_MustBeDetected', 'kind': 'data', 'value': 'boolean', 'datatype': 'http://www.w3.org/2001/XMLSchema#boolean'})
    fault_kind_name: Mapped[str] = mapped_column('name', Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasFaultKind_Name', 'kind': 'data', 'value': 'text'})
    position: Mapped[int | None] = mapped_column(Integer(), nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFaultKind_Position', 'kind': 'data', 'value': 'integer', 'datatype': 'http://www.w3.org/2001/XMLSchema#positiveInteger'})
    rejecting: Mapped[bool | None] = mapped_column(Boolean(), nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFaultKind_Rejecting', 'kind': 'data', 'value': 'boolean', 'datatype': 'http://www.w3.org/2001/XMLSchema#boolean'})
    test_method_rate: Mapped[float | None] = mapped_column(_DECIMAL, nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFaultKind_TestMethodRate', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    action: Mapped[list[Action]] = relationship('Action', secondary=lambda: soap_has_fault_kind_action, primaryjoin=lambda: FaultKind.__table__.c.id == soap_has_fault_kind_action.c.subject_id, secondaryjoin=lambda: Action.__table__.c.id == soap_has_fault_kind_action.c.value_id, info={'iri': 'https://w3id.org/kitkb/soap#hasFaultKind_Action'})
    # also_names: values of <https://w3id.org/kitkb/soap#hasFaultKind_AlsoNames> are rows of table soap_has_fault_kind_also_names
    diagnosed_by: Mapped[list[FailureMode]] = relationship('FailureMode', secondary=lambda: soap_has_fault_kind_diagnosed_by, primaryjoin=lambda: FaultKind.__table__.c.id == soap_has_fault_kind_diagnosed_by.c.subject_id, secondaryjoin=lambda: FailureMode.__table__.c.id == soap_has_fault_kind_diagnosed_by.c.value_id, info={'iri': 'https://w3id.org/kitkb/soap#hasFaultKind_DiagnosedBy'})
    target: Mapped[list[Parameter]] = relationship('Parameter', secondary=lambda: soap_has_fault_kind_target, primaryjoin=lambda: FaultKind.__table__.c.id == soap_has_fault_kind_target.c.subject_id, secondaryjoin=lambda: Parameter.__table__.c.id == soap_has_fault_kind_target.c.value_id, info={'iri': 'https://w3id.org/kitkb/soap#hasFaultKind_Target'})


class FaultMechanism(Thing):
    """A primitive the simulated cell implements to make something go wrong (its code is per mechanism: kb/sim/faults.py). A mechanism that acts on an object changes the object a kind's target names when the struck action begins; the others arm the robot, which carries the fault out when its moment comes and reports it. Its distances are data (metres).

    Class <https://w3id.org/kitkb/soap#FaultMechanism>.
    """

    __tablename__ = 'soap_fault_mechanism'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#FaultMechanism', 'parent': 'kitkb_thing'}, 'comment': "A primitive the simulated cell implements to make something go wrong (its code is per mechanism: kb/sim/faults.py). A mechanism that acts on an object changes the object a kind's target names when the struck action begins; the others arm the robot, which carries the fault out when its moment comes and reports it. Its distances are data (metres)."}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#FaultMechanism', "inherit_condition": id.column == Thing.__table__.c.id}
    acts_on_object: Mapped[bool | None] = mapped_column(Boolean(), nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFaultMechanism_ActsOnObject', 'kind': 'data', 'value': 'boolean', 'datatype': 'http://www.w3.org/2001/XMLSchema#boolean'})
    beside: Mapped[float | None] = mapped_column(_DECIMAL, nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFaultMechanism_Beside', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    max_shift: Mapped[float | None] = mapped_column(_DECIMAL, nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFaultMechanism_MaxShift', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    min_shift: Mapped[float | None] = mapped_column(_DECIMAL, nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFaultMechanism_MinShift', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})


class Formula(Thing):
    """A Boolean condition tree: atoms combined by conjunction, disjunction, negation and existential quantification. Used for predicate definitions and for the discriminating conditions of failure modes.

    Class <https://w3id.org/kitkb/soap#Formula>.
    """

    __tablename__ = 'soap_formula'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Formula', 'parent': 'kitkb_thing'}, 'comment': 'A Boolean condition tree: atoms combined by conjunction, disjunction, negation and existential quantification. Used for predicate definitions and for the discriminating conditions of failure modes.'}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Formula', "inherit_condition": id.column == Thing.__table__.c.id}


class Function(Thing):
    """A named numeric state variable (a PDDL fluent) with a reference and an optional target parameter.

    Class <https://w3id.org/kitkb/soap#Function>.
    """

    __tablename__ = 'soap_function'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Function', 'parent': 'kitkb_thing'}, 'comment': 'A named numeric state variable (a PDDL fluent) with a reference and an optional target parameter.'}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Function', "inherit_condition": id.column == Thing.__table__.c.id}
    definition_id: Mapped[int] = mapped_column(Integer, _ref('soap_numeric_expression'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFunction_Definition', 'kind': 'object'})
    definition: Mapped[NumericExpression] = relationship('NumericExpression', primaryjoin=lambda: foreign(Function.__table__.c.definition_id) == remote(NumericExpression.__table__.c.id), foreign_keys=lambda: [Function.__table__.c.definition_id])
    function_name: Mapped[str] = mapped_column('name', Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasFunction_Name', 'kind': 'data', 'value': 'text'})
    reference_type: Mapped[str] = mapped_column(_IRI, nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasFunction_ReferenceType', 'kind': 'iri'})
    target_type: Mapped[str | None] = mapped_column(_IRI, nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFunction_TargetType', 'kind': 'iri'})


class FunctionComparison(Thing):
    """A numeric test in a precondition. The operator is given by the leaf class (…Equal, …Less, …Greater, …LessOrEqual, …GreaterOrEqual); the left side is the first operand.

    Class <https://w3id.org/kitkb/soap#FunctionComparison>.
    """

    __tablename__ = 'soap_function_comparison'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#FunctionComparison', 'parent': 'kitkb_thing'}, 'comment': 'A numeric test in a precondition. The operator is given by the leaf class (…Equal, …Less, …Greater, …LessOrEqual, …GreaterOrEqual); the left side is the first operand.'}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#FunctionComparison', "inherit_condition": id.column == Thing.__table__.c.id}
    first_operand_id: Mapped[int] = mapped_column(Integer, _ref('soap_function_term'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFunctionComparison_FirstOperand', 'kind': 'object'})
    first_operand: Mapped[FunctionTerm] = relationship('FunctionTerm', primaryjoin=lambda: foreign(FunctionComparison.__table__.c.first_operand_id) == remote(FunctionTerm.__table__.c.id), foreign_keys=lambda: [FunctionComparison.__table__.c.first_operand_id])


class FunctionTerm(Thing):
    """A use of a function with its arguments bound to an action's parameters, e.g. (quantity-kit ?kit ?sku).

    Class <https://w3id.org/kitkb/soap#FunctionTerm>.
    """

    __tablename__ = 'soap_function_term'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#FunctionTerm', 'parent': 'kitkb_thing'}, 'comment': "A use of a function with its arguments bound to an action's parameters, e.g. (quantity-kit ?kit ?sku)."}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#FunctionTerm', "inherit_condition": id.column == Thing.__table__.c.id}
    function_id: Mapped[int] = mapped_column(Integer, _ref('soap_function'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFunctionTerm_Function', 'kind': 'object'})
    function: Mapped[Function] = relationship('Function', primaryjoin=lambda: foreign(FunctionTerm.__table__.c.function_id) == remote(Function.__table__.c.id), foreign_keys=lambda: [FunctionTerm.__table__.c.function_id])
    reference_parameter_id: Mapped[int] = mapped_column(Integer, _ref('soap_term'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFunctionTerm_ReferenceParameter', 'kind': 'object'})
    reference_parameter: Mapped[Term] = relationship('Term', primaryjoin=lambda: foreign(FunctionTerm.__table__.c.reference_parameter_id) == remote(Term.__table__.c.id), foreign_keys=lambda: [FunctionTerm.__table__.c.reference_parameter_id])
    target_parameter_id: Mapped[int | None] = mapped_column(Integer, _ref('soap_term'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFunctionTerm_TargetParameter', 'kind': 'object'})
    target_parameter: Mapped[Term | None] = relationship('Term', primaryjoin=lambda: foreign(FunctionTerm.__table__.c.target_parameter_id) == remote(Term.__table__.c.id), foreign_keys=lambda: [FunctionTerm.__table__.c.target_parameter_id])


class Notification(Thing):
    """A message to a recipient (a department or role) about a failure.

    Class <https://w3id.org/kitkb/soap#Notification>.
    """

    __tablename__ = 'soap_notification'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Notification', 'parent': 'kitkb_thing'}, 'comment': 'A message to a recipient (a department or role) about a failure.'}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Notification', "inherit_condition": id.column == Thing.__table__.c.id}
    message: Mapped[str] = mapped_column(Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasNotification_Message', 'kind': 'data', 'value': 'text'})
    recipient: Mapped[str] = mapped_column(Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasNotification_Recipient', 'kind': 'data', 'value': 'text'})


class NumericEffect(Thing):
    """An update of a function term by a constant (hasNumericEffect_Amount) or by another function term (hasNumericEffect_AmountFunction), exactly one of the two. The kind of update is the leaf class: soap:IncreaseEffect, soap:DecreaseEffect, soap:AssignEffect.

    Class <https://w3id.org/kitkb/soap#NumericEffect>.
    """

    __tablename__ = 'soap_numeric_effect'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#NumericEffect', 'parent': 'kitkb_thing'}, 'comment': 'An update of a function term by a constant (hasNumericEffect_Amount) or by another function term (hasNumericEffect_AmountFunction), exactly one of the two. The kind of update is the leaf class: soap:IncreaseEffect, soap:DecreaseEffect, soap:AssignEffect.'}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#NumericEffect', "inherit_condition": id.column == Thing.__table__.c.id}
    amount: Mapped[float | None] = mapped_column(_DECIMAL, nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasNumericEffect_Amount', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    amount_function_id: Mapped[int | None] = mapped_column(Integer, _ref('soap_function_term'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasNumericEffect_AmountFunction', 'kind': 'object'})
    amount_function: Mapped[FunctionTerm | None] = relationship('FunctionTerm', primaryjoin=lambda: foreign(NumericEffect.__table__.c.amount_function_id) == remote(FunctionTerm.__table__.c.id), foreign_keys=lambda: [NumericEffect.__table__.c.amount_function_id])
    function_id: Mapped[int] = mapped_column(Integer, _ref('soap_function_term'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasNumericEffect_Function', 'kind': 'object'})
    function: Mapped[FunctionTerm] = relationship('FunctionTerm', primaryjoin=lambda: foreign(NumericEffect.__table__.c.function_id) == remote(FunctionTerm.__table__.c.id), foreign_keys=lambda: [NumericEffect.__table__.c.function_id])


class NumericExpression(Thing):
    """How a function's value is obtained from the cell.

    Class <https://w3id.org/kitkb/soap#NumericExpression>.
    """

    __tablename__ = 'soap_numeric_expression'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#NumericExpression', 'parent': 'kitkb_thing'}, 'comment': "How a function's value is obtained from the cell."}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#NumericExpression', "inherit_condition": id.column == Thing.__table__.c.id}


class ObjectConsequence(Thing):
    """What a failure mode implies about the object bound to one parameter of the failed action: its kind (soap:ConsequenceKind) and, optionally, the reason word the run reports (default: the kind's local name in lower case).

    Class <https://w3id.org/kitkb/soap#ObjectConsequence>.
    """

    __tablename__ = 'soap_object_consequence'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#ObjectConsequence', 'parent': 'kitkb_thing'}, 'comment': "What a failure mode implies about the object bound to one parameter of the failed action: its kind (soap:ConsequenceKind) and, optionally, the reason word the run reports (default: the kind's local name in lower case)."}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#ObjectConsequence', "inherit_condition": id.column == Thing.__table__.c.id}
    kind_id: Mapped[int] = mapped_column(Integer, _ref('soap_consequence_kind'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasObjectConsequence_Kind', 'kind': 'object'})
    object_consequence_kind: Mapped[ConsequenceKind] = relationship('ConsequenceKind', primaryjoin=lambda: foreign(ObjectConsequence.__table__.c.kind_id) == remote(ConsequenceKind.__table__.c.id), foreign_keys=lambda: [ObjectConsequence.__table__.c.kind_id])
    parameter_id: Mapped[int] = mapped_column(Integer, _ref('soap_parameter'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasObjectConsequence_Parameter', 'kind': 'object'})
    parameter: Mapped[Parameter] = relationship('Parameter', primaryjoin=lambda: foreign(ObjectConsequence.__table__.c.parameter_id) == remote(Parameter.__table__.c.id), foreign_keys=lambda: [ObjectConsequence.__table__.c.parameter_id])
    reason: Mapped[str | None] = mapped_column(Text(), nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasObjectConsequence_Reason', 'kind': 'data', 'value': 'text'})


class ParameterBinding(Thing):
    """Binds a parameter of a recovery step's action to the object of a parameter of the failed action, or to a named object of the cell (a reject place, say).

    Class <https://w3id.org/kitkb/soap#ParameterBinding>.
    """

    __tablename__ = 'soap_parameter_binding'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#ParameterBinding', 'parent': 'kitkb_thing'}, 'comment': "Binds a parameter of a recovery step's action to the object of a parameter of the failed action, or to a named object of the cell (a reject place, say)."}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#ParameterBinding', "inherit_condition": id.column == Thing.__table__.c.id}
    failed_parameter_id: Mapped[int | None] = mapped_column(Integer, _ref('soap_parameter'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasParameterBinding_FailedParameter', 'kind': 'object'})
    failed_parameter: Mapped[Parameter | None] = relationship('Parameter', primaryjoin=lambda: foreign(ParameterBinding.__table__.c.failed_parameter_id) == remote(Parameter.__table__.c.id), foreign_keys=lambda: [ParameterBinding.__table__.c.failed_parameter_id])
    object: Mapped[str | None] = mapped_column(_IRI, nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasParameterBinding_Object', 'kind': 'iri'})
    parameter_id: Mapped[int] = mapped_column(Integer, _ref('soap_parameter'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasParameterBinding_Parameter', 'kind': 'object'})
    parameter: Mapped[Parameter] = relationship('Parameter', primaryjoin=lambda: foreign(ParameterBinding.__table__.c.parameter_id) == remote(Parameter.__table__.c.id), foreign_keys=lambda: [ParameterBinding.__table__.c.parameter_id])


class PartialKitPolicy(Thing):
    """What the executor does with a kit it cannot finish; the individuals are soap:DeliverPartialKit and soap:LeaveKit, told apart by soap:hasPartialKitPolicy_Delivers.

    Class <https://w3id.org/kitkb/soap#PartialKitPolicy>.
    """

    __tablename__ = 'soap_partial_kit_policy'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#PartialKitPolicy', 'parent': 'kitkb_thing'}, 'comment': 'What the executor does with a kit it cannot finish; the individuals are soap:DeliverPartialKit and soap:LeaveKit, told apart by soap:hasPartialKitPolicy_Delivers.'}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#PartialKitPolicy', "inherit_condition": id.column == Thing.__table__.c.id}
    delivers: Mapped[bool | None] = mapped_column(Boolean(), nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasPartialKitPolicy_Delivers', 'kind': 'data', 'value': 'boolean', 'datatype': 'http://www.w3.org/2001/XMLSchema#boolean'})


class Precondition(Thing):
    """The conjunction of predicate atoms (each possibly negated) and numeric comparisons that must all hold before an action starts.

    Class <https://w3id.org/kitkb/soap#Precondition>.
    """

    __tablename__ = 'soap_precondition'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Precondition', 'parent': 'kitkb_thing'}, 'comment': 'The conjunction of predicate atoms (each possibly negated) and numeric comparisons that must all hold before an action starts.'}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Precondition', "inherit_condition": id.column == Thing.__table__.c.id}
    function_comparison: Mapped[list[FunctionComparison]] = relationship('FunctionComparison', secondary=lambda: soap_has_precondition_function_comparison, primaryjoin=lambda: Precondition.__table__.c.id == soap_has_precondition_function_comparison.c.subject_id, secondaryjoin=lambda: FunctionComparison.__table__.c.id == soap_has_precondition_function_comparison.c.value_id, info={'iri': 'https://w3id.org/kitkb/soap#hasPrecondition_FunctionComparison'})
    predicate_atom: Mapped[list[PredicateAtom]] = relationship('PredicateAtom', secondary=lambda: soap_has_precondition_predicate_atom, primaryjoin=lambda: Precondition.__table__.c.id == soap_has_precondition_predicate_atom.c.subject_id, secondaryjoin=lambda: PredicateAtom.__table__.c.id == soap_has_precondition_predicate_atom.c.value_id, info={'iri': 'https://w3id.org/kitkb/soap#hasPrecondition_PredicateAtom'})


class Predicate(Thing):
    """A named Boolean state variable with at most two parameters: a reference parameter and an optional target parameter (none for a flag). Its definition says how its truth is decided in the cell.

    Class <https://w3id.org/kitkb/soap#Predicate>.
    """

    __tablename__ = 'soap_predicate'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Predicate', 'parent': 'kitkb_thing'}, 'comment': 'A named Boolean state variable with at most two parameters: a reference parameter and an optional target parameter (none for a flag). Its definition says how its truth is decided in the cell.'}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Predicate', "inherit_condition": id.column == Thing.__table__.c.id}
    definition_id: Mapped[int] = mapped_column(Integer, _ref('soap_formula'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasPredicate_Definition', 'kind': 'object'})
    definition: Mapped[Formula] = relationship('Formula', primaryjoin=lambda: foreign(Predicate.__table__.c.definition_id) == remote(Formula.__table__.c.id), foreign_keys=lambda: [Predicate.__table__.c.definition_id])
    predicate_name: Mapped[str] = mapped_column('name', Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasPredicate_Name', 'kind': 'data', 'value': 'text'})
    reference_type: Mapped[str | None] = mapped_column(_IRI, nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasPredicate_ReferenceType', 'kind': 'iri'})
    target_type: Mapped[str | None] = mapped_column(_IRI, nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasPredicate_TargetType', 'kind': 'iri'})


class RecoveryPlan(Thing):
    """An ordered list of domain actions to run. A step's parameter is bound by its soap:ParameterBinding if it has one, else by name to the failed action's parameter of that name (or to an earlier step's), else to an object of the parameter's class for which the step action's preconditions over the parameters bound so far hold (the first by name).

    Class <https://w3id.org/kitkb/soap#RecoveryPlan>.
    """

    __tablename__ = 'soap_recovery_plan'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#RecoveryPlan', 'parent': 'kitkb_thing'}, 'comment': "An ordered list of domain actions to run. A step's parameter is bound by its soap:ParameterBinding if it has one, else by name to the failed action's parameter of that name (or to an earlier step's), else to an object of the parameter's class for which the step action's preconditions over the parameters bound so far hold (the first by name)."}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#RecoveryPlan', "inherit_condition": id.column == Thing.__table__.c.id}
    step: Mapped[list[RecoveryStep]] = relationship('RecoveryStep', secondary=lambda: soap_has_recovery_plan_step, primaryjoin=lambda: RecoveryPlan.__table__.c.id == soap_has_recovery_plan_step.c.subject_id, secondaryjoin=lambda: RecoveryStep.__table__.c.id == soap_has_recovery_plan_step.c.value_id, info={'iri': 'https://w3id.org/kitkb/soap#hasRecoveryPlan_Step'})


class RecoveryStep(Thing):
    """One action of a recovery plan at a position.

    Class <https://w3id.org/kitkb/soap#RecoveryStep>.
    """

    __tablename__ = 'soap_recovery_step'
    __table_args__ = (
        CheckConstraint(column('position') > literal(0), name='position_gt_0'),
        {'info': {'iri': 'https://w3id.org/kitkb/soap#RecoveryStep', 'parent': 'kitkb_thing'}, 'comment': 'One action of a recovery plan at a position.'},
    )

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#RecoveryStep', "inherit_condition": id.column == Thing.__table__.c.id}
    action_id: Mapped[int] = mapped_column(Integer, _ref('soap_action'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasRecoveryStep_Action', 'kind': 'object'})
    action: Mapped[Action] = relationship('Action', primaryjoin=lambda: foreign(RecoveryStep.__table__.c.action_id) == remote(Action.__table__.c.id), foreign_keys=lambda: [RecoveryStep.__table__.c.action_id])
    position: Mapped[int] = mapped_column(Integer(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasRecoveryStep_Position', 'kind': 'data', 'value': 'integer', 'datatype': 'http://www.w3.org/2001/XMLSchema#positiveInteger'})
    binding: Mapped[list[ParameterBinding]] = relationship('ParameterBinding', secondary=lambda: soap_has_recovery_step_binding, primaryjoin=lambda: RecoveryStep.__table__.c.id == soap_has_recovery_step_binding.c.subject_id, secondaryjoin=lambda: ParameterBinding.__table__.c.id == soap_has_recovery_step_binding.c.value_id, info={'iri': 'https://w3id.org/kitkb/soap#hasRecoveryStep_Binding'})


class RecoveryStrategy(Thing):
    """How to continue after a failure; the individuals are soap:RetryAction, soap:Replan, soap:ExecuteRecoveryPlan, soap:RebindObject, soap:RejectHeldObject and soap:Abort. The executor has one handler per individual (kb/execution/recovery.py).

    Class <https://w3id.org/kitkb/soap#RecoveryStrategy>.
    """

    __tablename__ = 'soap_recovery_strategy'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#RecoveryStrategy', 'parent': 'kitkb_thing'}, 'comment': 'How to continue after a failure; the individuals are soap:RetryAction, soap:Replan, soap:ExecuteRecoveryPlan, soap:RebindObject, soap:RejectHeldObject and soap:Abort. The executor has one handler per individual (kb/execution/recovery.py).'}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#RecoveryStrategy', "inherit_condition": id.column == Thing.__table__.c.id}


class SpatialRelation(Thing):
    """A spatial relation occurrence between an ordered pair (subject, object) of solid objects. Also the neutral element of the class expressions below: every pair is in it.

    Class <https://w3id.org/kitkb/soap#SpatialRelation>.
    """

    __tablename__ = 'soap_spatial_relation'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#SpatialRelation', 'parent': 'kitkb_thing'}, 'comment': 'A spatial relation occurrence between an ordered pair (subject, object) of solid objects. Also the neutral element of the class expressions below: every pair is in it.'}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#SpatialRelation', "inherit_condition": id.column == Thing.__table__.c.id}


class Term(Thing):
    """Something an atom can be about: an action parameter, a predicate's reference or target slot (soap:Reference, soap:Target), or a quantified variable.

    Class <https://w3id.org/kitkb/soap#Term>.
    """

    __tablename__ = 'soap_term'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Term', 'parent': 'kitkb_thing'}, 'comment': "Something an atom can be about: an action parameter, a predicate's reference or target slot (soap:Reference, soap:Target), or a quantified variable."}

    id: Mapped[int] = mapped_column(ForeignKey('kitkb_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Term', "inherit_condition": id.column == Thing.__table__.c.id}


class BoxVolume(DataThing):
    """An axis-aligned box given by two opposite corners: the minimum point and the maximum point, in the coordinate system where the box is located.

    Class <https://w3id.org/kitkb/kitting#BoxVolume>.
    """

    __tablename__ = 'ktw_box_volume'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#BoxVolume', 'parent': 'ktw_data_thing'}, 'comment': 'An axis-aligned box given by two opposite corners: the minimum point and the maximum point, in the coordinate system where the box is located.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_data_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#BoxVolume', "inherit_condition": id.column == DataThing.__table__.c.id}
    maximum_point_id: Mapped[int] = mapped_column(Integer, _ref('ktw_point'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasBoxVolume_MaximumPoint', 'kind': 'object'})
    maximum_point: Mapped[Point] = relationship('Point', primaryjoin=lambda: foreign(BoxVolume.__table__.c.maximum_point_id) == remote(Point.__table__.c.id), foreign_keys=lambda: [BoxVolume.__table__.c.maximum_point_id])
    minimum_point_id: Mapped[int] = mapped_column(Integer, _ref('ktw_point'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasBoxVolume_MinimumPoint', 'kind': 'object'})
    minimum_point: Mapped[Point] = relationship('Point', primaryjoin=lambda: foreign(BoxVolume.__table__.c.minimum_point_id) == remote(Point.__table__.c.id), foreign_keys=lambda: [BoxVolume.__table__.c.minimum_point_id])
    had_by_other_obstacle_kitting_workstation: Mapped[list[KittingWorkstation]] = relationship('KittingWorkstation', secondary=lambda: ktw_had_by_other_obstacle_kitting_workstation, primaryjoin=lambda: BoxVolume.__table__.c.id == ktw_had_by_other_obstacle_kitting_workstation.c.subject_id, secondaryjoin=lambda: KittingWorkstation.__table__.c.id == ktw_had_by_other_obstacle_kitting_workstation.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByOtherObstacle_KittingWorkstation'})
    had_by_work_volume_robot: Mapped[list[Robot]] = relationship('Robot', secondary=lambda: ktw_had_by_work_volume_robot, primaryjoin=lambda: BoxVolume.__table__.c.id == ktw_had_by_work_volume_robot.c.subject_id, secondaryjoin=lambda: Robot.__table__.c.id == ktw_had_by_work_volume_robot.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByWorkVolume_Robot'})


class KitDesign(DataThing):
    """What a kit should contain: the SKU of its kit tray and, for each part, its SKU and its pose on the tray.

    Class <https://w3id.org/kitkb/kitting#KitDesign>.
    """

    __tablename__ = 'ktw_kit_design'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#KitDesign', 'parent': 'ktw_data_thing'}, 'comment': 'What a kit should contain: the SKU of its kit tray and, for each part, its SKU and its pose on the tray.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_data_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#KitDesign', "inherit_condition": id.column == DataThing.__table__.c.id}
    kit_tray_sku_id: Mapped[int] = mapped_column(Integer, _ref('ktw_stock_keeping_unit'), index=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasKitDesign_KitTraySku', 'kind': 'object'})
    kit_tray_sku: Mapped[StockKeepingUnit] = relationship('StockKeepingUnit', primaryjoin=lambda: foreign(KitDesign.__table__.c.kit_tray_sku_id) == remote(StockKeepingUnit.__table__.c.id), foreign_keys=lambda: [KitDesign.__table__.c.kit_tray_sku_id])
    had_by_design_kit: Mapped[list[Kit]] = relationship('Kit', secondary=lambda: ktw_had_by_design_kit, primaryjoin=lambda: KitDesign.__table__.c.id == ktw_had_by_design_kit.c.subject_id, secondaryjoin=lambda: Kit.__table__.c.id == ktw_had_by_design_kit.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByDesign_Kit'})
    had_by_kit_design_kitting_workstation: Mapped[list[KittingWorkstation]] = relationship('KittingWorkstation', secondary=lambda: ktw_had_by_kit_design_kitting_workstation, primaryjoin=lambda: KitDesign.__table__.c.id == ktw_had_by_kit_design_kitting_workstation.c.subject_id, secondaryjoin=lambda: KittingWorkstation.__table__.c.id == ktw_had_by_kit_design_kitting_workstation.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByKitDesign_KittingWorkstation'})
    had_by_kit_design_large_box_with_kits: Mapped[list[LargeBoxWithKits]] = relationship('LargeBoxWithKits', secondary=lambda: ktw_had_by_kit_design_large_box_with_kits, primaryjoin=lambda: KitDesign.__table__.c.id == ktw_had_by_kit_design_large_box_with_kits.c.subject_id, secondaryjoin=lambda: LargeBoxWithKits.__table__.c.id == ktw_had_by_kit_design_large_box_with_kits.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByKitDesign_LargeBoxWithKits'})
    part_ref_and_pose: Mapped[list[PartRefAndPose]] = relationship('PartRefAndPose', secondary=lambda: ktw_has_kit_design_part_ref_and_pose, primaryjoin=lambda: KitDesign.__table__.c.id == ktw_has_kit_design_part_ref_and_pose.c.subject_id, secondaryjoin=lambda: PartRefAndPose.__table__.c.id == ktw_has_kit_design_part_ref_and_pose.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hasKitDesign_PartRefAndPose'})


class PartRefAndPose(DataThing):
    """One entry of a kit design: the SKU of a part and the pose (point, x axis, z axis) it should have relative to the kit tray.

    Class <https://w3id.org/kitkb/kitting#PartRefAndPose>.
    """

    __tablename__ = 'ktw_part_ref_and_pose'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#PartRefAndPose', 'parent': 'ktw_data_thing'}, 'comment': 'One entry of a kit design: the SKU of a part and the pose (point, x axis, z axis) it should have relative to the kit tray.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_data_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#PartRefAndPose', "inherit_condition": id.column == DataThing.__table__.c.id}
    point_id: Mapped[int] = mapped_column(Integer, _ref('ktw_point'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasPartRefAndPose_Point', 'kind': 'object'})
    point: Mapped[Point] = relationship('Point', primaryjoin=lambda: foreign(PartRefAndPose.__table__.c.point_id) == remote(Point.__table__.c.id), foreign_keys=lambda: [PartRefAndPose.__table__.c.point_id])
    sku_id: Mapped[int] = mapped_column(Integer, _ref('ktw_stock_keeping_unit'), index=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasPartRefAndPose_Sku', 'kind': 'object'})
    sku: Mapped[StockKeepingUnit] = relationship('StockKeepingUnit', primaryjoin=lambda: foreign(PartRefAndPose.__table__.c.sku_id) == remote(StockKeepingUnit.__table__.c.id), foreign_keys=lambda: [PartRefAndPose.__table__.c.sku_id])
    x_axis_id: Mapped[int] = mapped_column(Integer, _ref('ktw_vector'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasPartRefAndPose_XAxis', 'kind': 'object'})
    x_axis: Mapped[Vector] = relationship('Vector', primaryjoin=lambda: foreign(PartRefAndPose.__table__.c.x_axis_id) == remote(Vector.__table__.c.id), foreign_keys=lambda: [PartRefAndPose.__table__.c.x_axis_id])
    z_axis_id: Mapped[int] = mapped_column(Integer, _ref('ktw_vector'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasPartRefAndPose_ZAxis', 'kind': 'object'})
    z_axis: Mapped[Vector] = relationship('Vector', primaryjoin=lambda: foreign(PartRefAndPose.__table__.c.z_axis_id) == remote(Vector.__table__.c.id), foreign_keys=lambda: [PartRefAndPose.__table__.c.z_axis_id])
    had_by_part_ref_and_pose_kit_design: Mapped[list[KitDesign]] = relationship('KitDesign', secondary=lambda: ktw_had_by_part_ref_and_pose_kit_design, primaryjoin=lambda: PartRefAndPose.__table__.c.id == ktw_had_by_part_ref_and_pose_kit_design.c.subject_id, secondaryjoin=lambda: KitDesign.__table__.c.id == ktw_had_by_part_ref_and_pose_kit_design.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByPartRefAndPose_KitDesign'})
    had_by_part_ref_and_pose_slot: Mapped[list[Slot]] = relationship('Slot', secondary=lambda: ktw_had_by_part_ref_and_pose_slot, primaryjoin=lambda: PartRefAndPose.__table__.c.id == ktw_had_by_part_ref_and_pose_slot.c.subject_id, secondaryjoin=lambda: Slot.__table__.c.id == ktw_had_by_part_ref_and_pose_slot.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByPartRefAndPose_Slot'})


class PhysicalLocation(DataThing):
    """Abstract: where a solid object is, always relative to a reference solid object, optionally time-stamped.

    Class <https://w3id.org/kitkb/kitting#PhysicalLocation>.
    """

    __tablename__ = 'ktw_physical_location'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#PhysicalLocation', 'parent': 'ktw_data_thing'}, 'comment': 'Abstract: where a solid object is, always relative to a reference solid object, optionally time-stamped.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_data_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#PhysicalLocation', "inherit_condition": id.column == DataThing.__table__.c.id}
    ref_object_id: Mapped[int] = mapped_column(Integer, _ref('ktw_solid_object'), index=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasPhysicalLocation_RefObject', 'kind': 'object'})
    ref_object: Mapped[SolidObject] = relationship('SolidObject', primaryjoin=lambda: foreign(PhysicalLocation.__table__.c.ref_object_id) == remote(SolidObject.__table__.c.id), foreign_keys=lambda: [PhysicalLocation.__table__.c.ref_object_id])
    timestamp: Mapped[datetime.datetime | None] = mapped_column(DateTime(timezone=True), nullable=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasPhysicalLocation_Timestamp', 'kind': 'data', 'value': 'datetime', 'datatype': 'http://www.w3.org/2001/XMLSchema#dateTime'})
    had_by_primary_location_solid_object: Mapped[list[SolidObject]] = relationship('SolidObject', secondary=lambda: ktw_had_by_primary_location_solid_object, primaryjoin=lambda: PhysicalLocation.__table__.c.id == ktw_had_by_primary_location_solid_object.c.subject_id, secondaryjoin=lambda: SolidObject.__table__.c.id == ktw_had_by_primary_location_solid_object.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByPrimaryLocation_SolidObject'})
    had_by_secondary_location_solid_object: Mapped[list[SolidObject]] = relationship('SolidObject', secondary=lambda: ktw_had_by_secondary_location_solid_object, primaryjoin=lambda: PhysicalLocation.__table__.c.id == ktw_had_by_secondary_location_solid_object.c.subject_id, secondaryjoin=lambda: SolidObject.__table__.c.id == ktw_had_by_secondary_location_solid_object.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadBySecondaryLocation_SolidObject'})


class Point(DataThing):
    """A point given by its x, y and z coordinates in the length unit of the workstation.

    Class <https://w3id.org/kitkb/kitting#Point>.
    """

    __tablename__ = 'ktw_point'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#Point', 'parent': 'ktw_data_thing'}, 'comment': 'A point given by its x, y and z coordinates in the length unit of the workstation.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_data_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#Point', "inherit_condition": id.column == DataThing.__table__.c.id}
    x: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasPoint_X', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    y: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasPoint_Y', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    z: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasPoint_Z', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    had_by_maximum_point_box_volume: Mapped[list[BoxVolume]] = relationship('BoxVolume', secondary=lambda: ktw_had_by_maximum_point_box_volume, primaryjoin=lambda: Point.__table__.c.id == ktw_had_by_maximum_point_box_volume.c.subject_id, secondaryjoin=lambda: BoxVolume.__table__.c.id == ktw_had_by_maximum_point_box_volume.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByMaximumPoint_BoxVolume'})
    had_by_minimum_point_box_volume: Mapped[list[BoxVolume]] = relationship('BoxVolume', secondary=lambda: ktw_had_by_minimum_point_box_volume, primaryjoin=lambda: Point.__table__.c.id == ktw_had_by_minimum_point_box_volume.c.subject_id, secondaryjoin=lambda: BoxVolume.__table__.c.id == ktw_had_by_minimum_point_box_volume.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByMinimumPoint_BoxVolume'})
    had_by_point_part_ref_and_pose: Mapped[list[PartRefAndPose]] = relationship('PartRefAndPose', secondary=lambda: ktw_had_by_point_part_ref_and_pose, primaryjoin=lambda: Point.__table__.c.id == ktw_had_by_point_part_ref_and_pose.c.subject_id, secondaryjoin=lambda: PartRefAndPose.__table__.c.id == ktw_had_by_point_part_ref_and_pose.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByPoint_PartRefAndPose'})
    had_by_point_pose_location: Mapped[list[PoseLocation]] = relationship('PoseLocation', secondary=lambda: ktw_had_by_point_pose_location, primaryjoin=lambda: Point.__table__.c.id == ktw_had_by_point_pose_location.c.subject_id, secondaryjoin=lambda: PoseLocation.__table__.c.id == ktw_had_by_point_pose_location.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByPoint_PoseLocation'})


class PoseSensor(DataThing):
    """The sensor that reports the poses and stock keeping units of the objects of a kitting workstation, with its accuracy: the standard deviation of a look's position and orientation errors, of a per-object position offset that further looks do not average out, and the chances that an object is not reported or reported with another SKU. A property not given is 0 (exact). Not in the NIST model: kitkb's, for verification under sensor noise.

    Class <https://w3id.org/kitkb/kitting#PoseSensor>.
    """

    __tablename__ = 'ktw_pose_sensor'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#PoseSensor', 'parent': 'ktw_data_thing'}, 'comment': "The sensor that reports the poses and stock keeping units of the objects of a kitting workstation, with its accuracy: the standard deviation of a look's position and orientation errors, of a per-object position offset that further looks do not average out, and the chances that an object is not reported or reported with another SKU. A property not given is 0 (exact). Not in the NIST model: kitkb's, for verification under sensor noise."}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_data_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#PoseSensor', "inherit_condition": id.column == DataThing.__table__.c.id}
    misclassification_rate: Mapped[float | None] = mapped_column(_DECIMAL, nullable=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasPoseSensor_MisclassificationRate', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    misdetection_rate: Mapped[float | None] = mapped_column(_DECIMAL, nullable=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasPoseSensor_MisdetectionRate', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    orientation_accuracy: Mapped[float | None] = mapped_column(_DECIMAL, nullable=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasPoseSensor_OrientationAccuracy', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    position_accuracy: Mapped[float | None] = mapped_column(_DECIMAL, nullable=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasPoseSensor_PositionAccuracy', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    position_bias: Mapped[float | None] = mapped_column(_DECIMAL, nullable=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasPoseSensor_PositionBias', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    had_by_sensor_kitting_workstation: Mapped[list[KittingWorkstation]] = relationship('KittingWorkstation', secondary=lambda: ktw_had_by_sensor_kitting_workstation, primaryjoin=lambda: PoseSensor.__table__.c.id == ktw_had_by_sensor_kitting_workstation.c.subject_id, secondaryjoin=lambda: KittingWorkstation.__table__.c.id == ktw_had_by_sensor_kitting_workstation.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadBySensor_KittingWorkstation'})


class ShapeDesign(DataThing):
    """Abstract: the shape of an object, with a description and an optional grasp pose.

    Class <https://w3id.org/kitkb/kitting#ShapeDesign>.
    """

    __tablename__ = 'ktw_shape_design'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#ShapeDesign', 'parent': 'ktw_data_thing'}, 'comment': 'Abstract: the shape of an object, with a description and an optional grasp pose.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_data_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#ShapeDesign', "inherit_condition": id.column == DataThing.__table__.c.id}
    description: Mapped[str] = mapped_column(Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasShapeDesign_Description', 'kind': 'data', 'value': 'text'})
    grasp_pose_id: Mapped[int | None] = mapped_column(Integer, _ref('ktw_pose_location'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasShapeDesign_GraspPose', 'kind': 'object'})
    grasp_pose: Mapped[PoseLocation | None] = relationship('PoseLocation', primaryjoin=lambda: foreign(ShapeDesign.__table__.c.grasp_pose_id) == remote(PoseLocation.__table__.c.id), foreign_keys=lambda: [ShapeDesign.__table__.c.grasp_pose_id])


class Slot(DataThing):
    """A place in a kit, tied to one entry of the kit design and possibly to the part that fills it.

    Class <https://w3id.org/kitkb/kitting#Slot>.
    """

    __tablename__ = 'ktw_slot'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#Slot', 'parent': 'ktw_data_thing'}, 'comment': 'A place in a kit, tied to one entry of the kit design and possibly to the part that fills it.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_data_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#Slot', "inherit_condition": id.column == DataThing.__table__.c.id}
    part_id: Mapped[int | None] = mapped_column(Integer, _ref('ktw_part'), index=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasSlot_Part', 'kind': 'object'})
    part: Mapped[Part | None] = relationship('Part', primaryjoin=lambda: foreign(Slot.__table__.c.part_id) == remote(Part.__table__.c.id), foreign_keys=lambda: [Slot.__table__.c.part_id])
    part_ref_and_pose_id: Mapped[int] = mapped_column(Integer, _ref('ktw_part_ref_and_pose'), index=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasSlot_PartRefAndPose', 'kind': 'object'})
    part_ref_and_pose: Mapped[PartRefAndPose] = relationship('PartRefAndPose', primaryjoin=lambda: foreign(Slot.__table__.c.part_ref_and_pose_id) == remote(PartRefAndPose.__table__.c.id), foreign_keys=lambda: [Slot.__table__.c.part_ref_and_pose_id])
    had_by_slot_kit: Mapped[list[Kit]] = relationship('Kit', secondary=lambda: ktw_had_by_slot_kit, primaryjoin=lambda: Slot.__table__.c.id == ktw_had_by_slot_kit.c.subject_id, secondaryjoin=lambda: Kit.__table__.c.id == ktw_had_by_slot_kit.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadBySlot_Kit'})


class StockKeepingUnit(DataThing):
    """A kind of stocked item: its description, shape, weight, and the end effectors able to handle it.

    Class <https://w3id.org/kitkb/kitting#StockKeepingUnit>.
    """

    __tablename__ = 'ktw_stock_keeping_unit'
    __table_args__ = (
        CheckConstraint(column('weight') > literal(0.0), name='weight_gt_0'),
        {'info': {'iri': 'https://w3id.org/kitkb/kitting#StockKeepingUnit', 'parent': 'ktw_data_thing'}, 'comment': 'A kind of stocked item: its description, shape, weight, and the end effectors able to handle it.'},
    )

    id: Mapped[int] = mapped_column(ForeignKey('ktw_data_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#StockKeepingUnit', "inherit_condition": id.column == DataThing.__table__.c.id}
    description: Mapped[str] = mapped_column(Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasStockKeepingUnit_Description', 'kind': 'data', 'value': 'text'})
    external_shape_id: Mapped[int | None] = mapped_column(Integer, _ref('ktw_external_shape'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasStockKeepingUnit_ExternalShape', 'kind': 'object'})
    external_shape: Mapped[ExternalShape | None] = relationship('ExternalShape', primaryjoin=lambda: foreign(StockKeepingUnit.__table__.c.external_shape_id) == remote(ExternalShape.__table__.c.id), foreign_keys=lambda: [StockKeepingUnit.__table__.c.external_shape_id])
    internal_shape_id: Mapped[int | None] = mapped_column(Integer, _ref('ktw_internal_shape'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasStockKeepingUnit_InternalShape', 'kind': 'object'})
    internal_shape: Mapped[InternalShape | None] = relationship('InternalShape', primaryjoin=lambda: foreign(StockKeepingUnit.__table__.c.internal_shape_id) == remote(InternalShape.__table__.c.id), foreign_keys=lambda: [StockKeepingUnit.__table__.c.internal_shape_id])
    weight: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasStockKeepingUnit_Weight', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    had_by_kit_tray_sku_kit_design: Mapped[list[KitDesign]] = relationship('KitDesign', secondary=lambda: ktw_had_by_kit_tray_sku_kit_design, primaryjoin=lambda: StockKeepingUnit.__table__.c.id == ktw_had_by_kit_tray_sku_kit_design.c.subject_id, secondaryjoin=lambda: KitDesign.__table__.c.id == ktw_had_by_kit_tray_sku_kit_design.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByKitTraySku_KitDesign'})
    had_by_part_sku_parts_vessel: Mapped[list[PartsVessel]] = relationship('PartsVessel', secondary=lambda: ktw_had_by_part_sku_parts_vessel, primaryjoin=lambda: StockKeepingUnit.__table__.c.id == ktw_had_by_part_sku_parts_vessel.c.subject_id, secondaryjoin=lambda: PartsVessel.__table__.c.id == ktw_had_by_part_sku_parts_vessel.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByPartSku_PartsVessel'})
    had_by_sku_kitting_workstation: Mapped[list[KittingWorkstation]] = relationship('KittingWorkstation', secondary=lambda: ktw_had_by_sku_kitting_workstation, primaryjoin=lambda: StockKeepingUnit.__table__.c.id == ktw_had_by_sku_kitting_workstation.c.subject_id, secondaryjoin=lambda: KittingWorkstation.__table__.c.id == ktw_had_by_sku_kitting_workstation.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadBySku_KittingWorkstation'})
    had_by_sku_part_ref_and_pose: Mapped[list[PartRefAndPose]] = relationship('PartRefAndPose', secondary=lambda: ktw_had_by_sku_part_ref_and_pose, primaryjoin=lambda: StockKeepingUnit.__table__.c.id == ktw_had_by_sku_part_ref_and_pose.c.subject_id, secondaryjoin=lambda: PartRefAndPose.__table__.c.id == ktw_had_by_sku_part_ref_and_pose.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadBySku_PartRefAndPose'})
    had_by_sku_sku_object: Mapped[list[SkuObject]] = relationship('SkuObject', secondary=lambda: ktw_had_by_sku_sku_object, primaryjoin=lambda: StockKeepingUnit.__table__.c.id == ktw_had_by_sku_sku_object.c.subject_id, secondaryjoin=lambda: SkuObject.__table__.c.id == ktw_had_by_sku_sku_object.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadBySku_SkuObject'})
    end_effector: Mapped[list[EndEffector]] = relationship('EndEffector', secondary=lambda: ktw_has_stock_keeping_unit_end_effector, primaryjoin=lambda: StockKeepingUnit.__table__.c.id == ktw_has_stock_keeping_unit_end_effector.c.subject_id, secondaryjoin=lambda: EndEffector.__table__.c.id == ktw_has_stock_keeping_unit_end_effector.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hasStockKeepingUnit_EndEffector'})


class Vector(DataThing):
    """A direction given by its i, j and k components.

    Class <https://w3id.org/kitkb/kitting#Vector>.
    """

    __tablename__ = 'ktw_vector'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#Vector', 'parent': 'ktw_data_thing'}, 'comment': 'A direction given by its i, j and k components.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_data_thing.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#Vector', "inherit_condition": id.column == DataThing.__table__.c.id}
    i: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasVector_I', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    j: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasVector_J', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    k: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasVector_K', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    had_by_x_axis_part_ref_and_pose: Mapped[list[PartRefAndPose]] = relationship('PartRefAndPose', secondary=lambda: ktw_had_by_x_axis_part_ref_and_pose, primaryjoin=lambda: Vector.__table__.c.id == ktw_had_by_x_axis_part_ref_and_pose.c.subject_id, secondaryjoin=lambda: PartRefAndPose.__table__.c.id == ktw_had_by_x_axis_part_ref_and_pose.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByXAxis_PartRefAndPose'})
    had_by_x_axis_pose_location: Mapped[list[PoseLocation]] = relationship('PoseLocation', secondary=lambda: ktw_had_by_x_axis_pose_location, primaryjoin=lambda: Vector.__table__.c.id == ktw_had_by_x_axis_pose_location.c.subject_id, secondaryjoin=lambda: PoseLocation.__table__.c.id == ktw_had_by_x_axis_pose_location.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByXAxis_PoseLocation'})
    had_by_z_axis_part_ref_and_pose: Mapped[list[PartRefAndPose]] = relationship('PartRefAndPose', secondary=lambda: ktw_had_by_z_axis_part_ref_and_pose, primaryjoin=lambda: Vector.__table__.c.id == ktw_had_by_z_axis_part_ref_and_pose.c.subject_id, secondaryjoin=lambda: PartRefAndPose.__table__.c.id == ktw_had_by_z_axis_part_ref_and_pose.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByZAxis_PartRefAndPose'})
    had_by_z_axis_pose_location: Mapped[list[PoseLocation]] = relationship('PoseLocation', secondary=lambda: ktw_had_by_z_axis_pose_location, primaryjoin=lambda: Vector.__table__.c.id == ktw_had_by_z_axis_pose_location.c.subject_id, secondaryjoin=lambda: PoseLocation.__table__.c.id == ktw_had_by_z_axis_pose_location.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByZAxis_PoseLocation'})


class BoxyObject(SolidObject):
    """A solid object whose shape is a box (trays, bins, containers, tables in Fig. 1 of the kit-building paper). Fig. 1 makes it the parent of KitTray, LargeContainer, PartsBin, PartsTray and WorkTable, but the NIST OWL model spreads those over SkuObject and NoSkuObject; following the NIST model, kitkb keeps BoxyObject as a direct subclass of SolidObject with no asserted subclasses, usable as an extra type. It is outside the NoSkuObject/SkuObject disjoint union.

    Class <https://w3id.org/kitkb/kitting#BoxyObject>.
    """

    __tablename__ = 'ktw_boxy_object'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#BoxyObject', 'parent': 'ktw_solid_object'}, 'comment': 'A solid object whose shape is a box (trays, bins, containers, tables in Fig. 1 of the kit-building paper). Fig. 1 makes it the parent of KitTray, LargeContainer, PartsBin, PartsTray and WorkTable, but the NIST OWL model spreads those over SkuObject and NoSkuObject; following the NIST model, kitkb keeps BoxyObject as a direct subclass of SolidObject with no asserted subclasses, usable as an extra type. It is outside the NoSkuObject/SkuObject disjoint union.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_solid_object.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#BoxyObject', "inherit_condition": id.column == SolidObject.__table__.c.id}


class NoSkuObject(SolidObject):
    """Abstract: solid objects that are not bought or stocked as items with a stock keeping unit (robots, tables, kits, changing stations, people, ...). They may carry their own shape.

    Class <https://w3id.org/kitkb/kitting#NoSkuObject>.
    """

    __tablename__ = 'ktw_no_sku_object'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#NoSkuObject', 'parent': 'ktw_solid_object'}, 'comment': 'Abstract: solid objects that are not bought or stocked as items with a stock keeping unit (robots, tables, kits, changing stations, people, ...). They may carry their own shape.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_solid_object.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#NoSkuObject', "inherit_condition": id.column == SolidObject.__table__.c.id}
    external_shape_id: Mapped[int | None] = mapped_column(Integer, _ref('ktw_external_shape'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasNoSkuObject_ExternalShape', 'kind': 'object'})
    external_shape: Mapped[ExternalShape | None] = relationship('ExternalShape', primaryjoin=lambda: foreign(NoSkuObject.__table__.c.external_shape_id) == remote(ExternalShape.__table__.c.id), foreign_keys=lambda: [NoSkuObject.__table__.c.external_shape_id])
    internal_shape_id: Mapped[int | None] = mapped_column(Integer, _ref('ktw_internal_shape'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasNoSkuObject_InternalShape', 'kind': 'object'})
    internal_shape: Mapped[InternalShape | None] = relationship('InternalShape', primaryjoin=lambda: foreign(NoSkuObject.__table__.c.internal_shape_id) == remote(InternalShape.__table__.c.id), foreign_keys=lambda: [NoSkuObject.__table__.c.internal_shape_id])


class SkuObject(SolidObject):
    """Abstract: solid objects that are stocked items; each one names the StockKeepingUnit that gives its shape, weight and grasping end effectors.

    Class <https://w3id.org/kitkb/kitting#SkuObject>.
    """

    __tablename__ = 'ktw_sku_object'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#SkuObject', 'parent': 'ktw_solid_object'}, 'comment': 'Abstract: solid objects that are stocked items; each one names the StockKeepingUnit that gives its shape, weight and grasping end effectors.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_solid_object.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#SkuObject', "inherit_condition": id.column == SolidObject.__table__.c.id}
    sku_id: Mapped[int] = mapped_column(Integer, _ref('ktw_stock_keeping_unit'), index=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasSkuObject_Sku', 'kind': 'object'})
    sku: Mapped[StockKeepingUnit] = relationship('StockKeepingUnit', primaryjoin=lambda: foreign(SkuObject.__table__.c.sku_id) == remote(StockKeepingUnit.__table__.c.id), foreign_keys=lambda: [SkuObject.__table__.c.sku_id])


class Atom(Formula):
    """A leaf of a formula. Every atom carries a negation flag; a negated atom holds exactly when its positive form does not.

    Class <https://w3id.org/kitkb/soap#Atom>.
    """

    __tablename__ = 'soap_atom'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Atom', 'parent': 'soap_formula'}, 'comment': 'A leaf of a formula. Every atom carries a negation flag; a negated atom holds exactly when its positive form does not.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_formula.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Atom', "inherit_condition": id.column == Formula.__table__.c.id}
    is_negated: Mapped[bool] = mapped_column(Boolean(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasAtom_IsNegated', 'kind': 'data', 'value': 'boolean', 'datatype': 'http://www.w3.org/2001/XMLSchema#boolean'})


class Conjunction(Formula):
    """Holds when all its operands hold.

    Class <https://w3id.org/kitkb/soap#Conjunction>.
    """

    __tablename__ = 'soap_conjunction'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Conjunction', 'parent': 'soap_formula'}, 'comment': 'Holds when all its operands hold.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_formula.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Conjunction', "inherit_condition": id.column == Formula.__table__.c.id}
    operand: Mapped[list[Formula]] = relationship('Formula', secondary=lambda: soap_has_conjunction_operand, primaryjoin=lambda: Conjunction.__table__.c.id == soap_has_conjunction_operand.c.subject_id, secondaryjoin=lambda: Formula.__table__.c.id == soap_has_conjunction_operand.c.value_id, info={'iri': 'https://w3id.org/kitkb/soap#hasConjunction_Operand'})


class Disjunction(Formula):
    """Holds when at least one operand holds.

    Class <https://w3id.org/kitkb/soap#Disjunction>.
    """

    __tablename__ = 'soap_disjunction'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Disjunction', 'parent': 'soap_formula'}, 'comment': 'Holds when at least one operand holds.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_formula.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Disjunction', "inherit_condition": id.column == Formula.__table__.c.id}
    operand: Mapped[list[Formula]] = relationship('Formula', secondary=lambda: soap_has_disjunction_operand, primaryjoin=lambda: Disjunction.__table__.c.id == soap_has_disjunction_operand.c.subject_id, secondaryjoin=lambda: Formula.__table__.c.id == soap_has_disjunction_operand.c.value_id, info={'iri': 'https://w3id.org/kitkb/soap#hasDisjunction_Operand'})


class Existential(Formula):
    """Holds when some individual of the variable's class (other than the objects bound to the enclosing terms) makes the body true. This is how a predicate refers to a third object, e.g. 'not in contact with any robot'.

    Class <https://w3id.org/kitkb/soap#Existential>.
    """

    __tablename__ = 'soap_existential'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Existential', 'parent': 'soap_formula'}, 'comment': "Holds when some individual of the variable's class (other than the objects bound to the enclosing terms) makes the body true. This is how a predicate refers to a third object, e.g. 'not in contact with any robot'."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_formula.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Existential', "inherit_condition": id.column == Formula.__table__.c.id}
    body_id: Mapped[int] = mapped_column(Integer, _ref('soap_formula'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasExistential_Body', 'kind': 'object'})
    body: Mapped[Formula] = relationship('Formula', primaryjoin=lambda: foreign(Existential.__table__.c.body_id) == remote(Formula.__table__.c.id), foreign_keys=lambda: [Existential.__table__.c.body_id])
    variable_id: Mapped[int] = mapped_column(Integer, _ref('soap_variable'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasExistential_Variable', 'kind': 'object'})
    variable: Mapped[Variable] = relationship('Variable', primaryjoin=lambda: foreign(Existential.__table__.c.variable_id) == remote(Variable.__table__.c.id), foreign_keys=lambda: [Existential.__table__.c.variable_id])


class Negation(Formula):
    """Holds when its single operand does not. Atoms are negated with hasAtom_IsNegated; this node negates compound formulas (typically an existential: 'there is no X such that ...').

    Class <https://w3id.org/kitkb/soap#Negation>.
    """

    __tablename__ = 'soap_negation'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Negation', 'parent': 'soap_formula'}, 'comment': "Holds when its single operand does not. Atoms are negated with hasAtom_IsNegated; this node negates compound formulas (typically an existential: 'there is no X such that ...')."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_formula.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Negation', "inherit_condition": id.column == Formula.__table__.c.id}
    operand_id: Mapped[int] = mapped_column(Integer, _ref('soap_formula'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasNegation_Operand', 'kind': 'object'})
    operand: Mapped[Formula] = relationship('Formula', primaryjoin=lambda: foreign(Negation.__table__.c.operand_id) == remote(Formula.__table__.c.id), foreign_keys=lambda: [Negation.__table__.c.operand_id])


class FunctionToDecimal(FunctionComparison):
    """Compares a function term with a constant.

    Class <https://w3id.org/kitkb/soap#FunctionToDecimal>.
    """

    __tablename__ = 'soap_function_to_decimal'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#FunctionToDecimal', 'parent': 'soap_function_comparison'}, 'comment': 'Compares a function term with a constant.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_function_comparison.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#FunctionToDecimal', "inherit_condition": id.column == FunctionComparison.__table__.c.id}
    second_operand: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasFunctionToDecimal_SecondOperand', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})


class FunctionToFunction(FunctionComparison):
    """Compares two function terms.

    Class <https://w3id.org/kitkb/soap#FunctionToFunction>.
    """

    __tablename__ = 'soap_function_to_function'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#FunctionToFunction', 'parent': 'soap_function_comparison'}, 'comment': 'Compares two function terms.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_function_comparison.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#FunctionToFunction', "inherit_condition": id.column == FunctionComparison.__table__.c.id}
    second_operand_id: Mapped[int] = mapped_column(Integer, _ref('soap_function_term'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasFunctionToFunction_SecondOperand', 'kind': 'object'})
    second_operand: Mapped[FunctionTerm] = relationship('FunctionTerm', primaryjoin=lambda: foreign(FunctionToFunction.__table__.c.second_operand_id) == remote(FunctionTerm.__table__.c.id), foreign_keys=lambda: [FunctionToFunction.__table__.c.second_operand_id])


class AssignEffect(NumericEffect):
    """Sets the function term to the amount (PDDL assign).

    Class <https://w3id.org/kitkb/soap#AssignEffect>.
    """

    __tablename__ = 'soap_assign_effect'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#AssignEffect', 'parent': 'soap_numeric_effect'}, 'comment': 'Sets the function term to the amount (PDDL assign).'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_numeric_effect.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#AssignEffect', "inherit_condition": id.column == NumericEffect.__table__.c.id}


class DecreaseEffect(NumericEffect):
    """Subtracts the amount from the function term (PDDL decrease).

    Class <https://w3id.org/kitkb/soap#DecreaseEffect>.
    """

    __tablename__ = 'soap_decrease_effect'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#DecreaseEffect', 'parent': 'soap_numeric_effect'}, 'comment': 'Subtracts the amount from the function term (PDDL decrease).'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_numeric_effect.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#DecreaseEffect', "inherit_condition": id.column == NumericEffect.__table__.c.id}


class IncreaseEffect(NumericEffect):
    """Adds the amount to the function term (PDDL increase).

    Class <https://w3id.org/kitkb/soap#IncreaseEffect>.
    """

    __tablename__ = 'soap_increase_effect'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#IncreaseEffect', 'parent': 'soap_numeric_effect'}, 'comment': 'Adds the amount to the function term (PDDL increase).'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_numeric_effect.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#IncreaseEffect', "inherit_condition": id.column == NumericEffect.__table__.c.id}


class CountExpression(NumericExpression):
    """The number of individuals of the variable's class meeting the condition (in which soap:Reference and soap:Target are the function's arguments).

    Class <https://w3id.org/kitkb/soap#CountExpression>.
    """

    __tablename__ = 'soap_count_expression'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#CountExpression', 'parent': 'soap_numeric_expression'}, 'comment': "The number of individuals of the variable's class meeting the condition (in which soap:Reference and soap:Target are the function's arguments)."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_numeric_expression.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#CountExpression', "inherit_condition": id.column == NumericExpression.__table__.c.id}
    condition_id: Mapped[int] = mapped_column(Integer, _ref('soap_formula'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasCountExpression_Condition', 'kind': 'object'})
    condition: Mapped[Formula] = relationship('Formula', primaryjoin=lambda: foreign(CountExpression.__table__.c.condition_id) == remote(Formula.__table__.c.id), foreign_keys=lambda: [CountExpression.__table__.c.condition_id])
    variable_id: Mapped[int] = mapped_column(Integer, _ref('soap_variable'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasCountExpression_Variable', 'kind': 'object'})
    variable: Mapped[Variable] = relationship('Variable', primaryjoin=lambda: foreign(CountExpression.__table__.c.variable_id) == remote(Variable.__table__.c.id), foreign_keys=lambda: [CountExpression.__table__.c.variable_id])


class DesignCountExpression(NumericExpression):
    """The number of part slots of a kit's design (ktw:hasKit_Design, ktw:hasKitDesign_PartRefAndPose) whose SKU (ktw:hasPartRefAndPose_Sku) is the target argument; the reference argument is the kit. Read from the model, not sensed.

    Class <https://w3id.org/kitkb/soap#DesignCountExpression>.
    """

    __tablename__ = 'soap_design_count_expression'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#DesignCountExpression', 'parent': 'soap_numeric_expression'}, 'comment': "The number of part slots of a kit's design (ktw:hasKit_Design, ktw:hasKitDesign_PartRefAndPose) whose SKU (ktw:hasPartRefAndPose_Sku) is the target argument; the reference argument is the kit. Read from the model, not sensed."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_numeric_expression.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#DesignCountExpression', "inherit_condition": id.column == NumericExpression.__table__.c.id}


class CardinalDirectionRelation(SpatialRelation):
    """Where the subject lies relative to the object along one axis, positive or negative direction (6 classes).

    Class <https://w3id.org/kitkb/soap#CardinalDirectionRelation>.
    """

    __tablename__ = 'soap_cardinal_direction_relation'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#CardinalDirectionRelation', 'parent': 'soap_spatial_relation'}, 'comment': 'Where the subject lies relative to the object along one axis, positive or negative direction (6 classes).'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_spatial_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#CardinalDirectionRelation', "inherit_condition": id.column == SpatialRelation.__table__.c.id}


class IntermediateStateRelation(SpatialRelation):
    """A reusable relation between two objects defined (owl:equivalentClass) by a Boolean combination of RCC8 and cardinal direction relations. Predicates are defined through these.

    Class <https://w3id.org/kitkb/soap#IntermediateStateRelation>.
    """

    __tablename__ = 'soap_intermediate_state_relation'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#IntermediateStateRelation', 'parent': 'soap_spatial_relation'}, 'comment': 'A reusable relation between two objects defined (owl:equivalentClass) by a Boolean combination of RCC8 and cardinal direction relations. Predicates are defined through these.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_spatial_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#IntermediateStateRelation', "inherit_condition": id.column == SpatialRelation.__table__.c.id}


class RCC8Relation(SpatialRelation):
    """One of the eight region connection calculus relations applied to the projections of subject and object on one axis (24 classes: 8 relations x 3 axes).

    Class <https://w3id.org/kitkb/soap#RCC8Relation>.
    """

    __tablename__ = 'soap_rcc8_relation'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#RCC8Relation', 'parent': 'soap_spatial_relation'}, 'comment': 'One of the eight region connection calculus relations applied to the projections of subject and object on one axis (24 classes: 8 relations x 3 axes).'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_spatial_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#RCC8Relation', "inherit_condition": id.column == SpatialRelation.__table__.c.id}


class Parameter(Term):
    """A typed, positioned parameter of one action (a PDDL ?variable).

    Class <https://w3id.org/kitkb/soap#Parameter>.
    """

    __tablename__ = 'soap_parameter'
    __table_args__ = (
        CheckConstraint(column('position') > literal(0), name='position_gt_0'),
        {'info': {'iri': 'https://w3id.org/kitkb/soap#Parameter', 'parent': 'soap_term'}, 'comment': 'A typed, positioned parameter of one action (a PDDL ?variable).'},
    )

    id: Mapped[int] = mapped_column(ForeignKey('soap_term.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Parameter', "inherit_condition": id.column == Term.__table__.c.id}
    parameter_name: Mapped[str] = mapped_column('name', Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasParameter_Name', 'kind': 'data', 'value': 'text'})
    next_id: Mapped[int | None] = mapped_column(Integer, _ref('soap_parameter'), unique=True, info={'iri': 'https://w3id.org/kitkb/soap#hasParameter_Next', 'kind': 'object'})
    next: Mapped[Parameter | None] = relationship('Parameter', primaryjoin=lambda: foreign(Parameter.__table__.c.next_id) == remote(Parameter.__table__.c.id), foreign_keys=lambda: [Parameter.__table__.c.next_id])
    position: Mapped[int] = mapped_column(Integer(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasParameter_Position', 'kind': 'data', 'value': 'integer', 'datatype': 'http://www.w3.org/2001/XMLSchema#positiveInteger'})
    previous_id: Mapped[int | None] = mapped_column(Integer, _ref('soap_parameter'), unique=True, info={'iri': 'https://w3id.org/kitkb/soap#hasParameter_Previous', 'kind': 'object'})
    previous: Mapped[Parameter | None] = relationship('Parameter', primaryjoin=lambda: foreign(Parameter.__table__.c.previous_id) == remote(Parameter.__table__.c.id), foreign_keys=lambda: [Parameter.__table__.c.previous_id])
    type: Mapped[str] = mapped_column(_IRI, nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasParameter_Type', 'kind': 'iri'})


class Variable(Term):
    """A quantified term ranging over the individuals of one kitting class that are present in the cell, excluding the objects already bound to the other terms of the enclosing formula.

    Class <https://w3id.org/kitkb/soap#Variable>.
    """

    __tablename__ = 'soap_variable'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Variable', 'parent': 'soap_term'}, 'comment': 'A quantified term ranging over the individuals of one kitting class that are present in the cell, excluding the objects already bound to the other terms of the enclosing formula.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_term.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Variable', "inherit_condition": id.column == Term.__table__.c.id}
    class_: Mapped[str] = mapped_column('class', _IRI, nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasVariable_Class', 'kind': 'iri'})
    variable_name: Mapped[str] = mapped_column('name', Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasVariable_Name', 'kind': 'data', 'value': 'text'})


class PoseLocation(PhysicalLocation):
    """Abstract: a location given as a full pose (origin point, x axis and z axis) in the coordinate system of the reference object, with optional position and orientation standard deviations.

    Class <https://w3id.org/kitkb/kitting#PoseLocation>.
    """

    __tablename__ = 'ktw_pose_location'
    __table_args__ = (
        CheckConstraint(column('orientation_standard_deviation') > literal(0.0), name='orientation_standard_deviation_gt_0'),
        CheckConstraint(column('position_standard_deviation') > literal(0.0), name='position_standard_deviation_gt_0'),
        {'info': {'iri': 'https://w3id.org/kitkb/kitting#PoseLocation', 'parent': 'ktw_physical_location'}, 'comment': 'Abstract: a location given as a full pose (origin point, x axis and z axis) in the coordinate system of the reference object, with optional position and orientation standard deviations.'},
    )

    id: Mapped[int] = mapped_column(ForeignKey('ktw_physical_location.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#PoseLocation', "inherit_condition": id.column == PhysicalLocation.__table__.c.id}
    orientation_standard_deviation: Mapped[float | None] = mapped_column(_DECIMAL, nullable=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasPoseLocation_OrientationStandardDeviation', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    point_id: Mapped[int] = mapped_column(Integer, _ref('ktw_point'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasPoseLocation_Point', 'kind': 'object'})
    point: Mapped[Point] = relationship('Point', primaryjoin=lambda: foreign(PoseLocation.__table__.c.point_id) == remote(Point.__table__.c.id), foreign_keys=lambda: [PoseLocation.__table__.c.point_id])
    position_standard_deviation: Mapped[float | None] = mapped_column(_DECIMAL, nullable=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasPoseLocation_PositionStandardDeviation', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    x_axis_id: Mapped[int] = mapped_column(Integer, _ref('ktw_vector'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasPoseLocation_XAxis', 'kind': 'object'})
    x_axis: Mapped[Vector] = relationship('Vector', primaryjoin=lambda: foreign(PoseLocation.__table__.c.x_axis_id) == remote(Vector.__table__.c.id), foreign_keys=lambda: [PoseLocation.__table__.c.x_axis_id])
    z_axis_id: Mapped[int] = mapped_column(Integer, _ref('ktw_vector'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasPoseLocation_ZAxis', 'kind': 'object'})
    z_axis: Mapped[Vector] = relationship('Vector', primaryjoin=lambda: foreign(PoseLocation.__table__.c.z_axis_id) == remote(Vector.__table__.c.id), foreign_keys=lambda: [PoseLocation.__table__.c.z_axis_id])
    had_by_grasp_pose_shape_design: Mapped[list[ShapeDesign]] = relationship('ShapeDesign', secondary=lambda: ktw_had_by_grasp_pose_shape_design, primaryjoin=lambda: PoseLocation.__table__.c.id == ktw_had_by_grasp_pose_shape_design.c.subject_id, secondaryjoin=lambda: ShapeDesign.__table__.c.id == ktw_had_by_grasp_pose_shape_design.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByGraspPose_ShapeDesign'})


class RelativeLocation(PhysicalLocation):
    """Abstract: a qualitative location relative to a reference object, described in words.

    Class <https://w3id.org/kitkb/kitting#RelativeLocation>.
    """

    __tablename__ = 'ktw_relative_location'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#RelativeLocation', 'parent': 'ktw_physical_location'}, 'comment': 'Abstract: a qualitative location relative to a reference object, described in words.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_physical_location.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#RelativeLocation', "inherit_condition": id.column == PhysicalLocation.__table__.c.id}
    description: Mapped[str] = mapped_column(Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasRelativeLocation_Description', 'kind': 'data', 'value': 'text'})


class ExternalShape(ShapeDesign):
    """A shape kept in an external model file, named by file, format and optionally the model inside the file.

    Class <https://w3id.org/kitkb/kitting#ExternalShape>.
    """

    __tablename__ = 'ktw_external_shape'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#ExternalShape', 'parent': 'ktw_shape_design'}, 'comment': 'A shape kept in an external model file, named by file, format and optionally the model inside the file.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_shape_design.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#ExternalShape', "inherit_condition": id.column == ShapeDesign.__table__.c.id}
    model_file_name: Mapped[str] = mapped_column(Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasExternalShape_ModelFileName', 'kind': 'data', 'value': 'text'})
    model_format_name: Mapped[str] = mapped_column(Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasExternalShape_ModelFormatName', 'kind': 'data', 'value': 'text'})
    model_name: Mapped[str | None] = mapped_column(Text(), nullable=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasExternalShape_ModelName', 'kind': 'data', 'value': 'text'})
    had_by_external_shape_no_sku_object: Mapped[list[NoSkuObject]] = relationship('NoSkuObject', secondary=lambda: ktw_had_by_external_shape_no_sku_object, primaryjoin=lambda: ExternalShape.__table__.c.id == ktw_had_by_external_shape_no_sku_object.c.subject_id, secondaryjoin=lambda: NoSkuObject.__table__.c.id == ktw_had_by_external_shape_no_sku_object.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByExternalShape_NoSkuObject'})
    had_by_external_shape_stock_keeping_unit: Mapped[list[StockKeepingUnit]] = relationship('StockKeepingUnit', secondary=lambda: ktw_had_by_external_shape_stock_keeping_unit, primaryjoin=lambda: ExternalShape.__table__.c.id == ktw_had_by_external_shape_stock_keeping_unit.c.subject_id, secondaryjoin=lambda: StockKeepingUnit.__table__.c.id == ktw_had_by_external_shape_stock_keeping_unit.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByExternalShape_StockKeepingUnit'})


class InternalShape(ShapeDesign):
    """Abstract: a shape written out in the data itself.

    Class <https://w3id.org/kitkb/kitting#InternalShape>.
    """

    __tablename__ = 'ktw_internal_shape'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#InternalShape', 'parent': 'ktw_shape_design'}, 'comment': 'Abstract: a shape written out in the data itself.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_shape_design.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#InternalShape', "inherit_condition": id.column == ShapeDesign.__table__.c.id}
    had_by_internal_shape_no_sku_object: Mapped[list[NoSkuObject]] = relationship('NoSkuObject', secondary=lambda: ktw_had_by_internal_shape_no_sku_object, primaryjoin=lambda: InternalShape.__table__.c.id == ktw_had_by_internal_shape_no_sku_object.c.subject_id, secondaryjoin=lambda: NoSkuObject.__table__.c.id == ktw_had_by_internal_shape_no_sku_object.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByInternalShape_NoSkuObject'})
    had_by_internal_shape_stock_keeping_unit: Mapped[list[StockKeepingUnit]] = relationship('StockKeepingUnit', secondary=lambda: ktw_had_by_internal_shape_stock_keeping_unit, primaryjoin=lambda: InternalShape.__table__.c.id == ktw_had_by_internal_shape_stock_keeping_unit.c.subject_id, secondaryjoin=lambda: StockKeepingUnit.__table__.c.id == ktw_had_by_internal_shape_stock_keeping_unit.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByInternalShape_StockKeepingUnit'})


class EndEffector(NoSkuObject):
    """Abstract: a tool that a robot wears at the end of its arm, either on the robot or parked in an end effector holder. It may hold one object.

    Class <https://w3id.org/kitkb/kitting#EndEffector>.
    """

    __tablename__ = 'ktw_end_effector'
    __table_args__ = (
        CheckConstraint(column('maximum_load_weight') > literal(0.0), name='maximum_load_weight_gt_0'),
        CheckConstraint(column('weight') > literal(0.0), name='weight_gt_0'),
        {'info': {'iri': 'https://w3id.org/kitkb/kitting#EndEffector', 'parent': 'ktw_no_sku_object'}, 'comment': 'Abstract: a tool that a robot wears at the end of its arm, either on the robot or parked in an end effector holder. It may hold one object.'},
    )

    id: Mapped[int] = mapped_column(ForeignKey('ktw_no_sku_object.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#EndEffector', "inherit_condition": id.column == NoSkuObject.__table__.c.id}
    description: Mapped[str] = mapped_column(Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasEndEffector_Description', 'kind': 'data', 'value': 'text'})
    held_object_id: Mapped[int | None] = mapped_column(Integer, _ref('ktw_solid_object'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasEndEffector_HeldObject', 'kind': 'object'})
    held_object: Mapped[SolidObject | None] = relationship('SolidObject', primaryjoin=lambda: foreign(EndEffector.__table__.c.held_object_id) == remote(SolidObject.__table__.c.id), foreign_keys=lambda: [EndEffector.__table__.c.held_object_id])
    maximum_load_weight: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasEndEffector_MaximumLoadWeight', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    weight: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasEndEffector_Weight', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    had_by_end_effector_end_effector_holder: Mapped[list[EndEffectorHolder]] = relationship('EndEffectorHolder', secondary=lambda: ktw_had_by_end_effector_end_effector_holder, primaryjoin=lambda: EndEffector.__table__.c.id == ktw_had_by_end_effector_end_effector_holder.c.subject_id, secondaryjoin=lambda: EndEffectorHolder.__table__.c.id == ktw_had_by_end_effector_end_effector_holder.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByEndEffector_EndEffectorHolder'})
    had_by_end_effector_robot: Mapped[list[Robot]] = relationship('Robot', secondary=lambda: ktw_had_by_end_effector_robot, primaryjoin=lambda: EndEffector.__table__.c.id == ktw_had_by_end_effector_robot.c.subject_id, secondaryjoin=lambda: Robot.__table__.c.id == ktw_had_by_end_effector_robot.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByEndEffector_Robot'})
    had_by_end_effector_stock_keeping_unit: Mapped[list[StockKeepingUnit]] = relationship('StockKeepingUnit', secondary=lambda: ktw_had_by_end_effector_stock_keeping_unit, primaryjoin=lambda: EndEffector.__table__.c.id == ktw_had_by_end_effector_stock_keeping_unit.c.subject_id, secondaryjoin=lambda: StockKeepingUnit.__table__.c.id == ktw_had_by_end_effector_stock_keeping_unit.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByEndEffector_StockKeepingUnit'})


class EndEffectorChangingStation(NoSkuObject):
    """A passive station where end effectors are parked in holders and where the robot swaps them; it has a base and holders.

    Class <https://w3id.org/kitkb/kitting#EndEffectorChangingStation>.
    """

    __tablename__ = 'ktw_end_effector_changing_station'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#EndEffectorChangingStation', 'parent': 'ktw_no_sku_object'}, 'comment': 'A passive station where end effectors are parked in holders and where the robot swaps them; it has a base and holders.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_no_sku_object.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#EndEffectorChangingStation', "inherit_condition": id.column == NoSkuObject.__table__.c.id}
    base_id: Mapped[int] = mapped_column(Integer, _ref('ktw_mechanical_component'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasEndEffectorChangingStation_Base', 'kind': 'object'})
    base: Mapped[MechanicalComponent] = relationship('MechanicalComponent', primaryjoin=lambda: foreign(EndEffectorChangingStation.__table__.c.base_id) == remote(MechanicalComponent.__table__.c.id), foreign_keys=lambda: [EndEffectorChangingStation.__table__.c.base_id])
    had_by_changing_station_kitting_workstation: Mapped[list[KittingWorkstation]] = relationship('KittingWorkstation', secondary=lambda: ktw_had_by_changing_station_kitting_workstation, primaryjoin=lambda: EndEffectorChangingStation.__table__.c.id == ktw_had_by_changing_station_kitting_workstation.c.subject_id, secondaryjoin=lambda: KittingWorkstation.__table__.c.id == ktw_had_by_changing_station_kitting_workstation.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByChangingStation_KittingWorkstation'})
    end_effector_holder: Mapped[list[EndEffectorHolder]] = relationship('EndEffectorHolder', secondary=lambda: ktw_has_end_effector_changing_station_end_effector_holder, primaryjoin=lambda: EndEffectorChangingStation.__table__.c.id == ktw_has_end_effector_changing_station_end_effector_holder.c.subject_id, secondaryjoin=lambda: EndEffectorHolder.__table__.c.id == ktw_has_end_effector_changing_station_end_effector_holder.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hasEndEffectorChangingStation_EndEffectorHolder'})


class EndEffectorHolder(NoSkuObject):
    """A place in an end effector changing station that stores zero or one end effector.

    Class <https://w3id.org/kitkb/kitting#EndEffectorHolder>.
    """

    __tablename__ = 'ktw_end_effector_holder'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#EndEffectorHolder', 'parent': 'ktw_no_sku_object'}, 'comment': 'A place in an end effector changing station that stores zero or one end effector.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_no_sku_object.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#EndEffectorHolder', "inherit_condition": id.column == NoSkuObject.__table__.c.id}
    end_effector_id: Mapped[int | None] = mapped_column(Integer, _ref('ktw_end_effector'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasEndEffectorHolder_EndEffector', 'kind': 'object'})
    end_effector: Mapped[EndEffector | None] = relationship('EndEffector', primaryjoin=lambda: foreign(EndEffectorHolder.__table__.c.end_effector_id) == remote(EndEffector.__table__.c.id), foreign_keys=lambda: [EndEffectorHolder.__table__.c.end_effector_id])
    had_by_end_effector_holder_end_effector_changing_station: Mapped[list[EndEffectorChangingStation]] = relationship('EndEffectorChangingStation', secondary=lambda: ktw_had_by_end_effector_holder_end_effector_changing_station, primaryjoin=lambda: EndEffectorHolder.__table__.c.id == ktw_had_by_end_effector_holder_end_effector_changing_station.c.subject_id, secondaryjoin=lambda: EndEffectorChangingStation.__table__.c.id == ktw_had_by_end_effector_holder_end_effector_changing_station.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByEndEffectorHolder_EndEffectorChangingStation'})


class Human(NoSkuObject):
    """A person in the cell, described by a bounding shape.

    Class <https://w3id.org/kitkb/kitting#Human>.
    """

    __tablename__ = 'ktw_human'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#Human', 'parent': 'ktw_no_sku_object'}, 'comment': 'A person in the cell, described by a bounding shape.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_no_sku_object.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#Human', "inherit_condition": id.column == NoSkuObject.__table__.c.id}


class Kit(NoSkuObject):
    """A kit tray together with the parts put on it according to a kit design; it may record slots showing which places are filled, and whether it is finished.

    Class <https://w3id.org/kitkb/kitting#Kit>.
    """

    __tablename__ = 'ktw_kit'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#Kit', 'parent': 'ktw_no_sku_object'}, 'comment': 'A kit tray together with the parts put on it according to a kit design; it may record slots showing which places are filled, and whether it is finished.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_no_sku_object.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#Kit', "inherit_condition": id.column == NoSkuObject.__table__.c.id}
    design_id: Mapped[int] = mapped_column(Integer, _ref('ktw_kit_design'), index=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasKit_Design', 'kind': 'object'})
    design: Mapped[KitDesign] = relationship('KitDesign', primaryjoin=lambda: foreign(Kit.__table__.c.design_id) == remote(KitDesign.__table__.c.id), foreign_keys=lambda: [Kit.__table__.c.design_id])
    finished: Mapped[bool] = mapped_column(Boolean(), nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasKit_Finished', 'kind': 'data', 'value': 'boolean', 'datatype': 'http://www.w3.org/2001/XMLSchema#boolean'})
    kit_tray_id: Mapped[int] = mapped_column(Integer, _ref('ktw_kit_tray'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasKit_KitTray', 'kind': 'object'})
    kit_tray: Mapped[KitTray] = relationship('KitTray', primaryjoin=lambda: foreign(Kit.__table__.c.kit_tray_id) == remote(KitTray.__table__.c.id), foreign_keys=lambda: [Kit.__table__.c.kit_tray_id])
    had_by_kit_large_box_with_kits: Mapped[list[LargeBoxWithKits]] = relationship('LargeBoxWithKits', secondary=lambda: ktw_had_by_kit_large_box_with_kits, primaryjoin=lambda: Kit.__table__.c.id == ktw_had_by_kit_large_box_with_kits.c.subject_id, secondaryjoin=lambda: LargeBoxWithKits.__table__.c.id == ktw_had_by_kit_large_box_with_kits.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByKit_LargeBoxWithKits'})
    part: Mapped[list[Part]] = relationship('Part', secondary=lambda: ktw_has_kit_part, primaryjoin=lambda: Kit.__table__.c.id == ktw_has_kit_part.c.subject_id, secondaryjoin=lambda: Part.__table__.c.id == ktw_has_kit_part.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hasKit_Part'})
    slot: Mapped[list[Slot]] = relationship('Slot', secondary=lambda: ktw_has_kit_slot, primaryjoin=lambda: Kit.__table__.c.id == ktw_has_kit_slot.c.subject_id, secondaryjoin=lambda: Slot.__table__.c.id == ktw_has_kit_slot.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hasKit_Slot'})


class KittingWorkstation(NoSkuObject):
    """The whole kitting cell: robot, changing station, work table, objects, stock keeping units, kit designs, obstacles, and the units (angle, length, weight) in which all quantities of a data file are written. It is the root of all location chains.

    Class <https://w3id.org/kitkb/kitting#KittingWorkstation>.
    """

    __tablename__ = 'ktw_kitting_workstation'
    __table_args__ = (
        CheckConstraint(column('angle_unit').in_(['degree', 'radian']), name='angle_unit_in'),
        CheckConstraint(column('length_unit').in_(['meter', 'millimeter', 'inch']), name='length_unit_in'),
        CheckConstraint(column('weight_unit').in_(['kilogram', 'gram', 'milligram', 'ounce', 'pound']), name='weight_unit_in'),
        {'info': {'iri': 'https://w3id.org/kitkb/kitting#KittingWorkstation', 'parent': 'ktw_no_sku_object'}, 'comment': 'The whole kitting cell: robot, changing station, work table, objects, stock keeping units, kit designs, obstacles, and the units (angle, length, weight) in which all quantities of a data file are written. It is the root of all location chains.'},
    )

    id: Mapped[int] = mapped_column(ForeignKey('ktw_no_sku_object.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#KittingWorkstation', "inherit_condition": id.column == NoSkuObject.__table__.c.id}
    angle_unit: Mapped[str] = mapped_column(_IRI, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasKittingWorkstation_AngleUnit', 'kind': 'data', 'value': 'text'})
    changing_station_id: Mapped[int] = mapped_column(Integer, _ref('ktw_end_effector_changing_station'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasKittingWorkstation_ChangingStation', 'kind': 'object'})
    changing_station: Mapped[EndEffectorChangingStation] = relationship('EndEffectorChangingStation', primaryjoin=lambda: foreign(KittingWorkstation.__table__.c.changing_station_id) == remote(EndEffectorChangingStation.__table__.c.id), foreign_keys=lambda: [KittingWorkstation.__table__.c.changing_station_id])
    length_unit: Mapped[str] = mapped_column(_IRI, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasKittingWorkstation_LengthUnit', 'kind': 'data', 'value': 'text'})
    robot_id: Mapped[int] = mapped_column(Integer, _ref('ktw_robot'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasKittingWorkstation_Robot', 'kind': 'object'})
    robot: Mapped[Robot] = relationship('Robot', primaryjoin=lambda: foreign(KittingWorkstation.__table__.c.robot_id) == remote(Robot.__table__.c.id), foreign_keys=lambda: [KittingWorkstation.__table__.c.robot_id])
    sensor_id: Mapped[int | None] = mapped_column(Integer, _ref('ktw_pose_sensor'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasKittingWorkstation_Sensor', 'kind': 'object'})
    sensor: Mapped[PoseSensor | None] = relationship('PoseSensor', primaryjoin=lambda: foreign(KittingWorkstation.__table__.c.sensor_id) == remote(PoseSensor.__table__.c.id), foreign_keys=lambda: [KittingWorkstation.__table__.c.sensor_id])
    weight_unit: Mapped[str] = mapped_column(_IRI, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasKittingWorkstation_WeightUnit', 'kind': 'data', 'value': 'text'})
    kit_design: Mapped[list[KitDesign]] = relationship('KitDesign', secondary=lambda: ktw_has_kitting_workstation_kit_design, primaryjoin=lambda: KittingWorkstation.__table__.c.id == ktw_has_kitting_workstation_kit_design.c.subject_id, secondaryjoin=lambda: KitDesign.__table__.c.id == ktw_has_kitting_workstation_kit_design.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hasKittingWorkstation_KitDesign'})
    object: Mapped[list[SolidObject]] = relationship('SolidObject', secondary=lambda: ktw_has_kitting_workstation_object, primaryjoin=lambda: KittingWorkstation.__table__.c.id == ktw_has_kitting_workstation_object.c.subject_id, secondaryjoin=lambda: SolidObject.__table__.c.id == ktw_has_kitting_workstation_object.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hasKittingWorkstation_Object'})
    other_obstacle: Mapped[list[BoxVolume]] = relationship('BoxVolume', secondary=lambda: ktw_has_kitting_workstation_other_obstacle, primaryjoin=lambda: KittingWorkstation.__table__.c.id == ktw_has_kitting_workstation_other_obstacle.c.subject_id, secondaryjoin=lambda: BoxVolume.__table__.c.id == ktw_has_kitting_workstation_other_obstacle.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hasKittingWorkstation_OtherObstacle'})
    sku: Mapped[list[StockKeepingUnit]] = relationship('StockKeepingUnit', secondary=lambda: ktw_has_kitting_workstation_sku, primaryjoin=lambda: KittingWorkstation.__table__.c.id == ktw_has_kitting_workstation_sku.c.subject_id, secondaryjoin=lambda: StockKeepingUnit.__table__.c.id == ktw_has_kitting_workstation_sku.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hasKittingWorkstation_Sku'})


class LargeBoxWithEmptyKitTrays(NoSkuObject):
    """A large container together with the empty kit trays it holds.

    Class <https://w3id.org/kitkb/kitting#LargeBoxWithEmptyKitTrays>.
    """

    __tablename__ = 'ktw_large_box_with_empty_kit_trays'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#LargeBoxWithEmptyKitTrays', 'parent': 'ktw_no_sku_object'}, 'comment': 'A large container together with the empty kit trays it holds.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_no_sku_object.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#LargeBoxWithEmptyKitTrays', "inherit_condition": id.column == NoSkuObject.__table__.c.id}
    large_container_id: Mapped[int] = mapped_column(Integer, _ref('ktw_large_container'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasLargeBoxWithEmptyKitTrays_LargeContainer', 'kind': 'object'})
    large_container: Mapped[LargeContainer] = relationship('LargeContainer', primaryjoin=lambda: foreign(LargeBoxWithEmptyKitTrays.__table__.c.large_container_id) == remote(LargeContainer.__table__.c.id), foreign_keys=lambda: [LargeBoxWithEmptyKitTrays.__table__.c.large_container_id])
    kit_tray: Mapped[list[KitTray]] = relationship('KitTray', secondary=lambda: ktw_has_large_box_with_empty_kit_trays_kit_tray, primaryjoin=lambda: LargeBoxWithEmptyKitTrays.__table__.c.id == ktw_has_large_box_with_empty_kit_trays_kit_tray.c.subject_id, secondaryjoin=lambda: KitTray.__table__.c.id == ktw_has_large_box_with_empty_kit_trays_kit_tray.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hasLargeBoxWithEmptyKitTrays_KitTray'})


class LargeBoxWithKits(NoSkuObject):
    """A large container together with the kits it holds, all of one kit design, up to a capacity.

    Class <https://w3id.org/kitkb/kitting#LargeBoxWithKits>.
    """

    __tablename__ = 'ktw_large_box_with_kits'
    __table_args__ = (
        CheckConstraint(column('capacity') > literal(0), name='capacity_gt_0'),
        {'info': {'iri': 'https://w3id.org/kitkb/kitting#LargeBoxWithKits', 'parent': 'ktw_no_sku_object'}, 'comment': 'A large container together with the kits it holds, all of one kit design, up to a capacity.'},
    )

    id: Mapped[int] = mapped_column(ForeignKey('ktw_no_sku_object.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#LargeBoxWithKits', "inherit_condition": id.column == NoSkuObject.__table__.c.id}
    capacity: Mapped[int] = mapped_column(Integer(), nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasLargeBoxWithKits_Capacity', 'kind': 'data', 'value': 'integer', 'datatype': 'http://www.w3.org/2001/XMLSchema#positiveInteger'})
    kit_design_id: Mapped[int] = mapped_column(Integer, _ref('ktw_kit_design'), index=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasLargeBoxWithKits_KitDesign', 'kind': 'object'})
    kit_design: Mapped[KitDesign] = relationship('KitDesign', primaryjoin=lambda: foreign(LargeBoxWithKits.__table__.c.kit_design_id) == remote(KitDesign.__table__.c.id), foreign_keys=lambda: [LargeBoxWithKits.__table__.c.kit_design_id])
    large_container_id: Mapped[int] = mapped_column(Integer, _ref('ktw_large_container'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasLargeBoxWithKits_LargeContainer', 'kind': 'object'})
    large_container: Mapped[LargeContainer] = relationship('LargeContainer', primaryjoin=lambda: foreign(LargeBoxWithKits.__table__.c.large_container_id) == remote(LargeContainer.__table__.c.id), foreign_keys=lambda: [LargeBoxWithKits.__table__.c.large_container_id])
    kit: Mapped[list[Kit]] = relationship('Kit', secondary=lambda: ktw_has_large_box_with_kits_kit, primaryjoin=lambda: LargeBoxWithKits.__table__.c.id == ktw_has_large_box_with_kits_kit.c.subject_id, secondaryjoin=lambda: Kit.__table__.c.id == ktw_has_large_box_with_kits_kit.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hasLargeBoxWithKits_Kit'})


class MechanicalComponent(NoSkuObject):
    """A plain mechanical part of the cell with no further structure, such as the base of a changing station.

    Class <https://w3id.org/kitkb/kitting#MechanicalComponent>.
    """

    __tablename__ = 'ktw_mechanical_component'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#MechanicalComponent', 'parent': 'ktw_no_sku_object'}, 'comment': 'A plain mechanical part of the cell with no further structure, such as the base of a changing station.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_no_sku_object.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#MechanicalComponent', "inherit_condition": id.column == NoSkuObject.__table__.c.id}
    had_by_base_end_effector_changing_station: Mapped[list[EndEffectorChangingStation]] = relationship('EndEffectorChangingStation', secondary=lambda: ktw_had_by_base_end_effector_changing_station, primaryjoin=lambda: MechanicalComponent.__table__.c.id == ktw_had_by_base_end_effector_changing_station.c.subject_id, secondaryjoin=lambda: EndEffectorChangingStation.__table__.c.id == ktw_had_by_base_end_effector_changing_station.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByBase_EndEffectorChangingStation'})


class Robot(NoSkuObject):
    """A one-armed robot with a description, a maximum load, optional work volumes and the end effector it currently wears, if any.

    Class <https://w3id.org/kitkb/kitting#Robot>.
    """

    __tablename__ = 'ktw_robot'
    __table_args__ = (
        CheckConstraint(column('maximum_load_weight') > literal(0.0), name='maximum_load_weight_gt_0'),
        {'info': {'iri': 'https://w3id.org/kitkb/kitting#Robot', 'parent': 'ktw_no_sku_object'}, 'comment': 'A one-armed robot with a description, a maximum load, optional work volumes and the end effector it currently wears, if any.'},
    )

    id: Mapped[int] = mapped_column(ForeignKey('ktw_no_sku_object.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#Robot', "inherit_condition": id.column == NoSkuObject.__table__.c.id}
    description: Mapped[str] = mapped_column(Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasRobot_Description', 'kind': 'data', 'value': 'text'})
    end_effector_id: Mapped[int | None] = mapped_column(Integer, _ref('ktw_end_effector'), unique=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasRobot_EndEffector', 'kind': 'object'})
    end_effector: Mapped[EndEffector | None] = relationship('EndEffector', primaryjoin=lambda: foreign(Robot.__table__.c.end_effector_id) == remote(EndEffector.__table__.c.id), foreign_keys=lambda: [Robot.__table__.c.end_effector_id])
    maximum_load_weight: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasRobot_MaximumLoadWeight', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    had_by_robot_kitting_workstation: Mapped[list[KittingWorkstation]] = relationship('KittingWorkstation', secondary=lambda: ktw_had_by_robot_kitting_workstation, primaryjoin=lambda: Robot.__table__.c.id == ktw_had_by_robot_kitting_workstation.c.subject_id, secondaryjoin=lambda: KittingWorkstation.__table__.c.id == ktw_had_by_robot_kitting_workstation.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByRobot_KittingWorkstation'})
    work_volume: Mapped[list[BoxVolume]] = relationship('BoxVolume', secondary=lambda: ktw_has_robot_work_volume, primaryjoin=lambda: Robot.__table__.c.id == ktw_has_robot_work_volume.c.subject_id, secondaryjoin=lambda: BoxVolume.__table__.c.id == ktw_has_robot_work_volume.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hasRobot_WorkVolume'})


class WorkTable(NoSkuObject):
    """A table on which objects (typically kit trays and parts vessels) are put for kitting; its shape is usually a BoxyShape. Fig. 1 places it under BoxyObject; kitkb follows NIST (NoSkuObject).

    Class <https://w3id.org/kitkb/kitting#WorkTable>.
    """

    __tablename__ = 'ktw_work_table'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#WorkTable', 'parent': 'ktw_no_sku_object'}, 'comment': 'A table on which objects (typically kit trays and parts vessels) are put for kitting; its shape is usually a BoxyShape. Fig. 1 places it under BoxyObject; kitkb follows NIST (NoSkuObject).'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_no_sku_object.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#WorkTable', "inherit_condition": id.column == NoSkuObject.__table__.c.id}
    object_on_table: Mapped[list[SolidObject]] = relationship('SolidObject', secondary=lambda: ktw_has_work_table_object_on_table, primaryjoin=lambda: WorkTable.__table__.c.id == ktw_has_work_table_object_on_table.c.subject_id, secondaryjoin=lambda: SolidObject.__table__.c.id == ktw_has_work_table_object_on_table.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hasWorkTable_ObjectOnTable'})


class KitTray(SkuObject):
    """A stocked tray with places on which the parts of one kit are laid. Fig. 1 places it under BoxyObject; kitkb follows NIST (SkuObject). Identified by its SKU together with its serial number.

    Class <https://w3id.org/kitkb/kitting#KitTray>.
    """

    __tablename__ = 'ktw_kit_tray'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#KitTray', 'parent': 'ktw_sku_object'}, 'comment': 'A stocked tray with places on which the parts of one kit are laid. Fig. 1 places it under BoxyObject; kitkb follows NIST (SkuObject). Identified by its SKU together with its serial number.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_sku_object.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#KitTray', "inherit_condition": id.column == SkuObject.__table__.c.id}
    serial_number: Mapped[str] = mapped_column(Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasKitTray_SerialNumber', 'kind': 'data', 'value': 'text', 'datatype': 'http://www.w3.org/2001/XMLSchema#NMTOKEN'})
    had_by_kit_tray_kit: Mapped[list[Kit]] = relationship('Kit', secondary=lambda: ktw_had_by_kit_tray_kit, primaryjoin=lambda: KitTray.__table__.c.id == ktw_had_by_kit_tray_kit.c.subject_id, secondaryjoin=lambda: Kit.__table__.c.id == ktw_had_by_kit_tray_kit.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByKitTray_Kit'})
    had_by_kit_tray_large_box_with_empty_kit_trays: Mapped[list[LargeBoxWithEmptyKitTrays]] = relationship('LargeBoxWithEmptyKitTrays', secondary=lambda: ktw_had_by_kit_tray_large_box_with_empty_kit_trays, primaryjoin=lambda: KitTray.__table__.c.id == ktw_had_by_kit_tray_large_box_with_empty_kit_trays.c.subject_id, secondaryjoin=lambda: LargeBoxWithEmptyKitTrays.__table__.c.id == ktw_had_by_kit_tray_large_box_with_empty_kit_trays.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByKitTray_LargeBoxWithEmptyKitTrays'})


class LargeContainer(SkuObject):
    """A stocked large box that holds kit trays or finished kits. Fig. 1 places it under BoxyObject; kitkb follows NIST (SkuObject). Identified by its SKU together with its serial number.

    Class <https://w3id.org/kitkb/kitting#LargeContainer>.
    """

    __tablename__ = 'ktw_large_container'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#LargeContainer', 'parent': 'ktw_sku_object'}, 'comment': 'A stocked large box that holds kit trays or finished kits. Fig. 1 places it under BoxyObject; kitkb follows NIST (SkuObject). Identified by its SKU together with its serial number.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_sku_object.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#LargeContainer', "inherit_condition": id.column == SkuObject.__table__.c.id}
    serial_number: Mapped[str] = mapped_column(Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasLargeContainer_SerialNumber', 'kind': 'data', 'value': 'text', 'datatype': 'http://www.w3.org/2001/XMLSchema#NMTOKEN'})
    had_by_large_container_large_box_with_empty_kit_trays: Mapped[list[LargeBoxWithEmptyKitTrays]] = relationship('LargeBoxWithEmptyKitTrays', secondary=lambda: ktw_had_by_large_container_large_box_with_empty_kit_trays, primaryjoin=lambda: LargeContainer.__table__.c.id == ktw_had_by_large_container_large_box_with_empty_kit_trays.c.subject_id, secondaryjoin=lambda: LargeBoxWithEmptyKitTrays.__table__.c.id == ktw_had_by_large_container_large_box_with_empty_kit_trays.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByLargeContainer_LargeBoxWithEmptyKitTrays'})
    had_by_large_container_large_box_with_kits: Mapped[list[LargeBoxWithKits]] = relationship('LargeBoxWithKits', secondary=lambda: ktw_had_by_large_container_large_box_with_kits, primaryjoin=lambda: LargeContainer.__table__.c.id == ktw_had_by_large_container_large_box_with_kits.c.subject_id, secondaryjoin=lambda: LargeBoxWithKits.__table__.c.id == ktw_had_by_large_container_large_box_with_kits.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByLargeContainer_LargeBoxWithKits'})


class Part(SkuObject):
    """A stocked item that goes into a kit. Identified by its SKU together with its serial number.

    Class <https://w3id.org/kitkb/kitting#Part>.
    """

    __tablename__ = 'ktw_part'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#Part', 'parent': 'ktw_sku_object'}, 'comment': 'A stocked item that goes into a kit. Identified by its SKU together with its serial number.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_sku_object.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#Part', "inherit_condition": id.column == SkuObject.__table__.c.id}
    serial_number: Mapped[str] = mapped_column(Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasPart_SerialNumber', 'kind': 'data', 'value': 'text', 'datatype': 'http://www.w3.org/2001/XMLSchema#NMTOKEN'})
    had_by_part_kit: Mapped[list[Kit]] = relationship('Kit', secondary=lambda: ktw_had_by_part_kit, primaryjoin=lambda: Part.__table__.c.id == ktw_had_by_part_kit.c.subject_id, secondaryjoin=lambda: Kit.__table__.c.id == ktw_had_by_part_kit.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByPart_Kit'})
    had_by_part_parts_vessel: Mapped[list[PartsVessel]] = relationship('PartsVessel', secondary=lambda: ktw_had_by_part_parts_vessel, primaryjoin=lambda: Part.__table__.c.id == ktw_had_by_part_parts_vessel.c.subject_id, secondaryjoin=lambda: PartsVessel.__table__.c.id == ktw_had_by_part_parts_vessel.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByPart_PartsVessel'})
    had_by_part_slot: Mapped[list[Slot]] = relationship('Slot', secondary=lambda: ktw_had_by_part_slot, primaryjoin=lambda: Part.__table__.c.id == ktw_had_by_part_slot.c.subject_id, secondaryjoin=lambda: Slot.__table__.c.id == ktw_had_by_part_slot.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hadByPart_Slot'})


class PartsVessel(SkuObject):
    """Abstract: a stocked container that supplies parts of one SKU (a bin or a tray), with a serial number and a count of the parts it holds.

    Class <https://w3id.org/kitkb/kitting#PartsVessel>.
    """

    __tablename__ = 'ktw_parts_vessel'
    __table_args__ = (
        CheckConstraint(column('part_quantity') >= literal(0), name='part_quantity_ge_0'),
        {'info': {'iri': 'https://w3id.org/kitkb/kitting#PartsVessel', 'parent': 'ktw_sku_object'}, 'comment': 'Abstract: a stocked container that supplies parts of one SKU (a bin or a tray), with a serial number and a count of the parts it holds.'},
    )

    id: Mapped[int] = mapped_column(ForeignKey('ktw_sku_object.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#PartsVessel', "inherit_condition": id.column == SkuObject.__table__.c.id}
    part_quantity: Mapped[int] = mapped_column(Integer(), nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasPartsVessel_PartQuantity', 'kind': 'data', 'value': 'integer', 'datatype': 'http://www.w3.org/2001/XMLSchema#nonNegativeInteger'})
    part_sku_id: Mapped[int] = mapped_column(Integer, _ref('ktw_stock_keeping_unit'), index=True, info={'iri': 'https://w3id.org/kitkb/kitting#hasPartsVessel_PartSku', 'kind': 'object'})
    part_sku: Mapped[StockKeepingUnit] = relationship('StockKeepingUnit', primaryjoin=lambda: foreign(PartsVessel.__table__.c.part_sku_id) == remote(StockKeepingUnit.__table__.c.id), foreign_keys=lambda: [PartsVessel.__table__.c.part_sku_id])
    serial_number: Mapped[str] = mapped_column(Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasPartsVessel_SerialNumber', 'kind': 'data', 'value': 'text', 'datatype': 'http://www.w3.org/2001/XMLSchema#NMTOKEN'})
    part: Mapped[list[Part]] = relationship('Part', secondary=lambda: ktw_has_parts_vessel_part, primaryjoin=lambda: PartsVessel.__table__.c.id == ktw_has_parts_vessel_part.c.subject_id, secondaryjoin=lambda: Part.__table__.c.id == ktw_has_parts_vessel_part.c.value_id, info={'iri': 'https://w3id.org/kitkb/kitting#hasPartsVessel_Part'})


class CountAtom(Atom):
    """Non-spatial at the top (kind 'count relation'), spatial underneath: counts the individuals of the variable's class that satisfy the condition and compares the count (operator one of < <= = >= >) with a limit. The limit is a constant (hasCountAtom_Limit) or the value of a kitting-model datatype property (hasCountAtom_LimitProperty) of the object bound to hasCountAtom_LimitSubject.

    Class <https://w3id.org/kitkb/soap#CountAtom>.
    """

    __tablename__ = 'soap_count_atom'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#CountAtom', 'parent': 'soap_atom'}, 'comment': "Non-spatial at the top (kind 'count relation'), spatial underneath: counts the individuals of the variable's class that satisfy the condition and compares the count (operator one of < <= = >= >) with a limit. The limit is a constant (hasCountAtom_Limit) or the value of a kitting-model datatype property (hasCountAtom_LimitProperty) of the object bound to hasCountAtom_LimitSubject."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_atom.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#CountAtom', "inherit_condition": id.column == Atom.__table__.c.id}
    condition_id: Mapped[int] = mapped_column(Integer, _ref('soap_formula'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasCountAtom_Condition', 'kind': 'object'})
    condition: Mapped[Formula] = relationship('Formula', primaryjoin=lambda: foreign(CountAtom.__table__.c.condition_id) == remote(Formula.__table__.c.id), foreign_keys=lambda: [CountAtom.__table__.c.condition_id])
    limit: Mapped[float | None] = mapped_column(_DECIMAL, nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasCountAtom_Limit', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    limit_property: Mapped[str | None] = mapped_column(Text(), nullable=True, info={'iri': 'https://w3id.org/kitkb/soap#hasCountAtom_LimitProperty', 'kind': 'data', 'value': 'text', 'datatype': 'http://www.w3.org/2001/XMLSchema#anyURI'})
    limit_subject_id: Mapped[int | None] = mapped_column(Integer, _ref('soap_term'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasCountAtom_LimitSubject', 'kind': 'object'})
    limit_subject: Mapped[Term | None] = relationship('Term', primaryjoin=lambda: foreign(CountAtom.__table__.c.limit_subject_id) == remote(Term.__table__.c.id), foreign_keys=lambda: [CountAtom.__table__.c.limit_subject_id])
    operator: Mapped[str] = mapped_column(Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasCountAtom_Operator', 'kind': 'data', 'value': 'text'})
    variable_id: Mapped[int] = mapped_column(Integer, _ref('soap_variable'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasCountAtom_Variable', 'kind': 'object'})
    variable: Mapped[Variable] = relationship('Variable', primaryjoin=lambda: foreign(CountAtom.__table__.c.variable_id) == remote(Variable.__table__.c.id), foreign_keys=lambda: [CountAtom.__table__.c.variable_id])


class ModelAtom(Atom):
    """Non-spatial (kind 'model relation'): holds when the kitting model states subject -property-> object, for the object property whose IRI is hasModelAtom_Property (e.g. ktw:hasSkuObject_Sku, ktw:hasKit_KitTray). Static facts such as identity and design data are decided this way.

    Class <https://w3id.org/kitkb/soap#ModelAtom>.
    """

    __tablename__ = 'soap_model_atom'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#ModelAtom', 'parent': 'soap_atom'}, 'comment': "Non-spatial (kind 'model relation'): holds when the kitting model states subject -property-> object, for the object property whose IRI is hasModelAtom_Property (e.g. ktw:hasSkuObject_Sku, ktw:hasKit_KitTray). Static facts such as identity and design data are decided this way."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_atom.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#ModelAtom', "inherit_condition": id.column == Atom.__table__.c.id}
    object_id: Mapped[int] = mapped_column(Integer, _ref('soap_term'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasModelAtom_Object', 'kind': 'object'})
    object: Mapped[Term] = relationship('Term', primaryjoin=lambda: foreign(ModelAtom.__table__.c.object_id) == remote(Term.__table__.c.id), foreign_keys=lambda: [ModelAtom.__table__.c.object_id])
    property: Mapped[str] = mapped_column(Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasModelAtom_Property', 'kind': 'data', 'value': 'text', 'datatype': 'http://www.w3.org/2001/XMLSchema#anyURI'})
    subject_id: Mapped[int] = mapped_column(Integer, _ref('soap_term'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasModelAtom_Subject', 'kind': 'object'})
    subject: Mapped[Term] = relationship('Term', primaryjoin=lambda: foreign(ModelAtom.__table__.c.subject_id) == remote(Term.__table__.c.id), foreign_keys=lambda: [ModelAtom.__table__.c.subject_id])


class PredicateAtom(Atom):
    """A use of a predicate with its arguments bound to terms: in an action, to the action's parameters; in a failure condition, to the failed action's parameters or to variables.

    Class <https://w3id.org/kitkb/soap#PredicateAtom>.
    """

    __tablename__ = 'soap_predicate_atom'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#PredicateAtom', 'parent': 'soap_atom'}, 'comment': "A use of a predicate with its arguments bound to terms: in an action, to the action's parameters; in a failure condition, to the failed action's parameters or to variables."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_atom.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#PredicateAtom', "inherit_condition": id.column == Atom.__table__.c.id}
    predicate_id: Mapped[int] = mapped_column(Integer, _ref('soap_predicate'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasPredicateAtom_Predicate', 'kind': 'object'})
    predicate: Mapped[Predicate] = relationship('Predicate', primaryjoin=lambda: foreign(PredicateAtom.__table__.c.predicate_id) == remote(Predicate.__table__.c.id), foreign_keys=lambda: [PredicateAtom.__table__.c.predicate_id])
    reference_parameter_id: Mapped[int | None] = mapped_column(Integer, _ref('soap_term'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasPredicateAtom_ReferenceParameter', 'kind': 'object'})
    reference_parameter: Mapped[Term | None] = relationship('Term', primaryjoin=lambda: foreign(PredicateAtom.__table__.c.reference_parameter_id) == remote(Term.__table__.c.id), foreign_keys=lambda: [PredicateAtom.__table__.c.reference_parameter_id])
    target_parameter_id: Mapped[int | None] = mapped_column(Integer, _ref('soap_term'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasPredicateAtom_TargetParameter', 'kind': 'object'})
    target_parameter: Mapped[Term | None] = relationship('Term', primaryjoin=lambda: foreign(PredicateAtom.__table__.c.target_parameter_id) == remote(Term.__table__.c.id), foreign_keys=lambda: [PredicateAtom.__table__.c.target_parameter_id])


class RelationAtom(Atom):
    """A spatial atom: relation(subject, object), decided from the two objects' poses and box shapes. The relation is an intermediate state relation class (decided through its owl:equivalentClass expression over RCC8 and cardinal direction classes) or directly an RCC8 or cardinal direction class.

    Class <https://w3id.org/kitkb/soap#RelationAtom>.
    """

    __tablename__ = 'soap_relation_atom'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#RelationAtom', 'parent': 'soap_atom'}, 'comment': "A spatial atom: relation(subject, object), decided from the two objects' poses and box shapes. The relation is an intermediate state relation class (decided through its owl:equivalentClass expression over RCC8 and cardinal direction classes) or directly an RCC8 or cardinal direction class."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_atom.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#RelationAtom', "inherit_condition": id.column == Atom.__table__.c.id}
    object_id: Mapped[int] = mapped_column(Integer, _ref('soap_term'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasRelationAtom_Object', 'kind': 'object'})
    object: Mapped[Term] = relationship('Term', primaryjoin=lambda: foreign(RelationAtom.__table__.c.object_id) == remote(Term.__table__.c.id), foreign_keys=lambda: [RelationAtom.__table__.c.object_id])
    relation: Mapped[str] = mapped_column(_IRI, nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasRelationAtom_Relation', 'kind': 'iri'})
    subject_id: Mapped[int] = mapped_column(Integer, _ref('soap_term'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasRelationAtom_Subject', 'kind': 'object'})
    subject: Mapped[Term] = relationship('Term', primaryjoin=lambda: foreign(RelationAtom.__table__.c.subject_id) == remote(Term.__table__.c.id), foreign_keys=lambda: [RelationAtom.__table__.c.subject_id])


class SensorAtom(Atom):
    """Non-spatial (kind 'sensor check'): holds when the named inspection of the subject passes (e.g. a quality inspection of a part). The check name is a key the executor maps to a sensor routine.

    Class <https://w3id.org/kitkb/soap#SensorAtom>.
    """

    __tablename__ = 'soap_sensor_atom'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#SensorAtom', 'parent': 'soap_atom'}, 'comment': "Non-spatial (kind 'sensor check'): holds when the named inspection of the subject passes (e.g. a quality inspection of a part). The check name is a key the executor maps to a sensor routine."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_atom.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#SensorAtom', "inherit_condition": id.column == Atom.__table__.c.id}
    check: Mapped[str] = mapped_column(Text(), nullable=False, info={'iri': 'https://w3id.org/kitkb/soap#hasSensorAtom_Check', 'kind': 'data', 'value': 'text'})
    subject_id: Mapped[int] = mapped_column(Integer, _ref('soap_term'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasSensorAtom_Subject', 'kind': 'object'})
    subject: Mapped[Term] = relationship('Term', primaryjoin=lambda: foreign(SensorAtom.__table__.c.subject_id) == remote(Term.__table__.c.id), foreign_keys=lambda: [SensorAtom.__table__.c.subject_id])


class SkuAtom(Atom):
    """Non-spatial (kind 'SKU relation'): holds when the end effector bound to the subject is one of the end effectors listed (ktw:hasStockKeepingUnit_EndEffector) by the stock keeping unit of the object bound to the object term (ktw:hasSkuObject_Sku; for a kit, the SKU of its kit tray, ktw:hasKit_KitTray).

    Class <https://w3id.org/kitkb/soap#SkuAtom>.
    """

    __tablename__ = 'soap_sku_atom'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#SkuAtom', 'parent': 'soap_atom'}, 'comment': "Non-spatial (kind 'SKU relation'): holds when the end effector bound to the subject is one of the end effectors listed (ktw:hasStockKeepingUnit_EndEffector) by the stock keeping unit of the object bound to the object term (ktw:hasSkuObject_Sku; for a kit, the SKU of its kit tray, ktw:hasKit_KitTray)."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_atom.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#SkuAtom', "inherit_condition": id.column == Atom.__table__.c.id}
    object_id: Mapped[int] = mapped_column(Integer, _ref('soap_term'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasSkuAtom_Object', 'kind': 'object'})
    object: Mapped[Term] = relationship('Term', primaryjoin=lambda: foreign(SkuAtom.__table__.c.object_id) == remote(Term.__table__.c.id), foreign_keys=lambda: [SkuAtom.__table__.c.object_id])
    subject_id: Mapped[int] = mapped_column(Integer, _ref('soap_term'), index=True, info={'iri': 'https://w3id.org/kitkb/soap#hasSkuAtom_Subject', 'kind': 'object'})
    subject: Mapped[Term] = relationship('Term', primaryjoin=lambda: foreign(SkuAtom.__table__.c.subject_id) == remote(Term.__table__.c.id), foreign_keys=lambda: [SkuAtom.__table__.c.subject_id])


class FunctionToDecimalEqual(FunctionToDecimal):
    """First operand = second operand (constant); PDDL (= first second).

    Class <https://w3id.org/kitkb/soap#FunctionToDecimalEqual>.
    """

    __tablename__ = 'soap_function_to_decimal_equal'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#FunctionToDecimalEqual', 'parent': 'soap_function_to_decimal'}, 'comment': 'First operand = second operand (constant); PDDL (= first second).'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_function_to_decimal.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#FunctionToDecimalEqual', "inherit_condition": id.column == FunctionToDecimal.__table__.c.id}


class FunctionToDecimalGreater(FunctionToDecimal):
    """First operand > second operand (constant); PDDL (> first second).

    Class <https://w3id.org/kitkb/soap#FunctionToDecimalGreater>.
    """

    __tablename__ = 'soap_function_to_decimal_greater'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#FunctionToDecimalGreater', 'parent': 'soap_function_to_decimal'}, 'comment': 'First operand > second operand (constant); PDDL (> first second).'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_function_to_decimal.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#FunctionToDecimalGreater', "inherit_condition": id.column == FunctionToDecimal.__table__.c.id}


class FunctionToDecimalGreaterOrEqual(FunctionToDecimal):
    """First operand >= second operand (constant); PDDL (>= first second).

    Class <https://w3id.org/kitkb/soap#FunctionToDecimalGreaterOrEqual>.
    """

    __tablename__ = 'soap_function_to_decimal_greater_or_equal'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#FunctionToDecimalGreaterOrEqual', 'parent': 'soap_function_to_decimal'}, 'comment': 'First operand >= second operand (constant); PDDL (>= first second).'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_function_to_decimal.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#FunctionToDecimalGreaterOrEqual', "inherit_condition": id.column == FunctionToDecimal.__table__.c.id}


class FunctionToDecimalLess(FunctionToDecimal):
    """First operand < second operand (constant); PDDL (< first second).

    Class <https://w3id.org/kitkb/soap#FunctionToDecimalLess>.
    """

    __tablename__ = 'soap_function_to_decimal_less'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#FunctionToDecimalLess', 'parent': 'soap_function_to_decimal'}, 'comment': 'First operand < second operand (constant); PDDL (< first second).'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_function_to_decimal.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#FunctionToDecimalLess', "inherit_condition": id.column == FunctionToDecimal.__table__.c.id}


class FunctionToDecimalLessOrEqual(FunctionToDecimal):
    """First operand <= second operand (constant); PDDL (<= first second).

    Class <https://w3id.org/kitkb/soap#FunctionToDecimalLessOrEqual>.
    """

    __tablename__ = 'soap_function_to_decimal_less_or_equal'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#FunctionToDecimalLessOrEqual', 'parent': 'soap_function_to_decimal'}, 'comment': 'First operand <= second operand (constant); PDDL (<= first second).'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_function_to_decimal.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#FunctionToDecimalLessOrEqual', "inherit_condition": id.column == FunctionToDecimal.__table__.c.id}


class FunctionToFunctionEqual(FunctionToFunction):
    """First operand = second operand (function term); PDDL (= first second).

    Class <https://w3id.org/kitkb/soap#FunctionToFunctionEqual>.
    """

    __tablename__ = 'soap_function_to_function_equal'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#FunctionToFunctionEqual', 'parent': 'soap_function_to_function'}, 'comment': 'First operand = second operand (function term); PDDL (= first second).'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_function_to_function.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#FunctionToFunctionEqual', "inherit_condition": id.column == FunctionToFunction.__table__.c.id}


class FunctionToFunctionGreater(FunctionToFunction):
    """First operand > second operand (function term); PDDL (> first second).

    Class <https://w3id.org/kitkb/soap#FunctionToFunctionGreater>.
    """

    __tablename__ = 'soap_function_to_function_greater'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#FunctionToFunctionGreater', 'parent': 'soap_function_to_function'}, 'comment': 'First operand > second operand (function term); PDDL (> first second).'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_function_to_function.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#FunctionToFunctionGreater', "inherit_condition": id.column == FunctionToFunction.__table__.c.id}


class FunctionToFunctionGreaterOrEqual(FunctionToFunction):
    """First operand >= second operand (function term); PDDL (>= first second).

    Class <https://w3id.org/kitkb/soap#FunctionToFunctionGreaterOrEqual>.
    """

    __tablename__ = 'soap_function_to_function_greater_or_equal'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#FunctionToFunctionGreaterOrEqual', 'parent': 'soap_function_to_function'}, 'comment': 'First operand >= second operand (function term); PDDL (>= first second).'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_function_to_function.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#FunctionToFunctionGreaterOrEqual', "inherit_condition": id.column == FunctionToFunction.__table__.c.id}


class FunctionToFunctionLess(FunctionToFunction):
    """First operand < second operand (function term); PDDL (< first second).

    Class <https://w3id.org/kitkb/soap#FunctionToFunctionLess>.
    """

    __tablename__ = 'soap_function_to_function_less'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#FunctionToFunctionLess', 'parent': 'soap_function_to_function'}, 'comment': 'First operand < second operand (function term); PDDL (< first second).'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_function_to_function.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#FunctionToFunctionLess', "inherit_condition": id.column == FunctionToFunction.__table__.c.id}


class FunctionToFunctionLessOrEqual(FunctionToFunction):
    """First operand <= second operand (function term); PDDL (<= first second).

    Class <https://w3id.org/kitkb/soap#FunctionToFunctionLessOrEqual>.
    """

    __tablename__ = 'soap_function_to_function_less_or_equal'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#FunctionToFunctionLessOrEqual', 'parent': 'soap_function_to_function'}, 'comment': 'First operand <= second operand (function term); PDDL (<= first second).'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_function_to_function.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#FunctionToFunctionLessOrEqual', "inherit_condition": id.column == FunctionToFunction.__table__.c.id}


class X_Minus(CardinalDirectionRelation):
    """The subject does not reach beyond the object along x: maxx(subject) <= maxx(object) (within tolerance). Combined with DC or EC it means 'entirely on the - side'.

    Class <https://w3id.org/kitkb/soap#X-Minus>.
    """

    __tablename__ = 'soap_x_minus'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#X-Minus', 'parent': 'soap_cardinal_direction_relation'}, 'comment': "The subject does not reach beyond the object along x: maxx(subject) <= maxx(object) (within tolerance). Combined with DC or EC it means 'entirely on the - side'."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_cardinal_direction_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#X-Minus', "inherit_condition": id.column == CardinalDirectionRelation.__table__.c.id}


class X_Plus(CardinalDirectionRelation):
    """The subject does not reach below the object along x: minx(subject) >= minx(object) (within tolerance). Combined with DC or EC it means 'entirely on the + side'.

    Class <https://w3id.org/kitkb/soap#X-Plus>.
    """

    __tablename__ = 'soap_x_plus'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#X-Plus', 'parent': 'soap_cardinal_direction_relation'}, 'comment': "The subject does not reach below the object along x: minx(subject) >= minx(object) (within tolerance). Combined with DC or EC it means 'entirely on the + side'."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_cardinal_direction_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#X-Plus', "inherit_condition": id.column == CardinalDirectionRelation.__table__.c.id}


class Y_Minus(CardinalDirectionRelation):
    """The subject does not reach beyond the object along y: maxy(subject) <= maxy(object) (within tolerance). Combined with DC or EC it means 'entirely on the - side'.

    Class <https://w3id.org/kitkb/soap#Y-Minus>.
    """

    __tablename__ = 'soap_y_minus'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Y-Minus', 'parent': 'soap_cardinal_direction_relation'}, 'comment': "The subject does not reach beyond the object along y: maxy(subject) <= maxy(object) (within tolerance). Combined with DC or EC it means 'entirely on the - side'."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_cardinal_direction_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Y-Minus', "inherit_condition": id.column == CardinalDirectionRelation.__table__.c.id}


class Y_Plus(CardinalDirectionRelation):
    """The subject does not reach below the object along y: miny(subject) >= miny(object) (within tolerance). Combined with DC or EC it means 'entirely on the + side'.

    Class <https://w3id.org/kitkb/soap#Y-Plus>.
    """

    __tablename__ = 'soap_y_plus'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Y-Plus', 'parent': 'soap_cardinal_direction_relation'}, 'comment': "The subject does not reach below the object along y: miny(subject) >= miny(object) (within tolerance). Combined with DC or EC it means 'entirely on the + side'."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_cardinal_direction_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Y-Plus', "inherit_condition": id.column == CardinalDirectionRelation.__table__.c.id}


class Z_Minus(CardinalDirectionRelation):
    """The subject does not reach beyond the object along z: maxz(subject) <= maxz(object) (within tolerance). Combined with DC or EC it means 'entirely on the - side'.

    Class <https://w3id.org/kitkb/soap#Z-Minus>.
    """

    __tablename__ = 'soap_z_minus'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Z-Minus', 'parent': 'soap_cardinal_direction_relation'}, 'comment': "The subject does not reach beyond the object along z: maxz(subject) <= maxz(object) (within tolerance). Combined with DC or EC it means 'entirely on the - side'."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_cardinal_direction_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Z-Minus', "inherit_condition": id.column == CardinalDirectionRelation.__table__.c.id}


class Z_Plus(CardinalDirectionRelation):
    """The subject does not reach below the object along z: minz(subject) >= minz(object) (within tolerance). Combined with DC or EC it means 'entirely on the + side'.

    Class <https://w3id.org/kitkb/soap#Z-Plus>.
    """

    __tablename__ = 'soap_z_plus'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Z-Plus', 'parent': 'soap_cardinal_direction_relation'}, 'comment': "The subject does not reach below the object along z: minz(subject) >= minz(object) (within tolerance). Combined with DC or EC it means 'entirely on the + side'."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_cardinal_direction_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Z-Plus', "inherit_condition": id.column == CardinalDirectionRelation.__table__.c.id}


class Contained_In(IntermediateStateRelation):
    """The subject's box lies entirely within the object's box on all three axes.

    Class <https://w3id.org/kitkb/soap#Contained-In>.
    """

    __tablename__ = 'soap_contained_in'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Contained-In', 'parent': 'soap_intermediate_state_relation'}, 'comment': "The subject's box lies entirely within the object's box on all three axes."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_intermediate_state_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Contained-In', "inherit_condition": id.column == IntermediateStateRelation.__table__.c.id}


class In_Contact_With(IntermediateStateRelation):
    """The subject touches the object: externally connected along x, y or z, and not apart along any axis. (The seeds' definition, X-EC or Y-EC or Z-EC alone, also holds for boxes that touch in one projection and are metres apart on another axis.)

    Class <https://w3id.org/kitkb/soap#In-Contact-With>.
    """

    __tablename__ = 'soap_in_contact_with'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#In-Contact-With', 'parent': 'soap_intermediate_state_relation'}, 'comment': "The subject touches the object: externally connected along x, y or z, and not apart along any axis. (The seeds' definition, X-EC or Y-EC or Z-EC alone, also holds for boxes that touch in one projection and are metres apart on another axis.)"}

    id: Mapped[int] = mapped_column(ForeignKey('soap_intermediate_state_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#In-Contact-With', "inherit_condition": id.column == IntermediateStateRelation.__table__.c.id}


class In_Or_Against(IntermediateStateRelation):
    """Partially-In or In-Contact-With: the subject sits in the object or rests against it, e.g. an end effector in its holder (kitkb's scenarios: inside the holder's box; NIST's files: hanging under a 1 mm holder plate) or a holder mounted in or on the side of a changing station's base.

    Class <https://w3id.org/kitkb/soap#In-Or-Against>.
    """

    __tablename__ = 'soap_in_or_against'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#In-Or-Against', 'parent': 'soap_intermediate_state_relation'}, 'comment': "Partially-In or In-Contact-With: the subject sits in the object or rests against it, e.g. an end effector in its holder (kitkb's scenarios: inside the holder's box; NIST's files: hanging under a 1 mm holder plate) or a holder mounted in or on the side of a changing station's base."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_intermediate_state_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#In-Or-Against', "inherit_condition": id.column == IntermediateStateRelation.__table__.c.id}


class Not_Contained_In(IntermediateStateRelation):
    """Complement of Contained-In.

    Class <https://w3id.org/kitkb/soap#Not-Contained-In>.
    """

    __tablename__ = 'soap_not_contained_in'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Not-Contained-In', 'parent': 'soap_intermediate_state_relation'}, 'comment': 'Complement of Contained-In.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_intermediate_state_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Not-Contained-In', "inherit_condition": id.column == IntermediateStateRelation.__table__.c.id}


class Not_In_Contact_With(IntermediateStateRelation):
    """Complement of In-Contact-With.

    Class <https://w3id.org/kitkb/soap#Not-In-Contact-With>.
    """

    __tablename__ = 'soap_not_in_contact_with'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Not-In-Contact-With', 'parent': 'soap_intermediate_state_relation'}, 'comment': 'Complement of In-Contact-With.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_intermediate_state_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Not-In-Contact-With', "inherit_condition": id.column == IntermediateStateRelation.__table__.c.id}


class On_Top_Of(IntermediateStateRelation):
    """The subject is above the object (disjoint or touching in z, on the + side) and their footprints overlap in x and y.

    Class <https://w3id.org/kitkb/soap#On-Top-Of>.
    """

    __tablename__ = 'soap_on_top_of'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#On-Top-Of', 'parent': 'soap_intermediate_state_relation'}, 'comment': 'The subject is above the object (disjoint or touching in z, on the + side) and their footprints overlap in x and y.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_intermediate_state_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#On-Top-Of', "inherit_condition": id.column == IntermediateStateRelation.__table__.c.id}


class On_Top_With_Contact(IntermediateStateRelation):
    """On-Top-Of and touching in z: the object supports the subject.

    Class <https://w3id.org/kitkb/soap#On-Top-With-Contact>.
    """

    __tablename__ = 'soap_on_top_with_contact'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#On-Top-With-Contact', 'parent': 'soap_intermediate_state_relation'}, 'comment': 'On-Top-Of and touching in z: the object supports the subject.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_intermediate_state_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#On-Top-With-Contact', "inherit_condition": id.column == IntermediateStateRelation.__table__.c.id}


class Partially_In(IntermediateStateRelation):
    """The subject is inside the object in x and y and at least partly inside it in z, not reaching below it (formula (2) of the simulated-sensor paper): e.g. a part in a parts tray or kit, a kit tray in a large box. EQ is admitted on each axis (formula (2) of the paper leaves it out, so a part exactly as tall as its kit tray, as in NIST's Goal1, would not be in it).

    Class <https://w3id.org/kitkb/soap#Partially-In>.
    """

    __tablename__ = 'soap_partially_in'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Partially-In', 'parent': 'soap_intermediate_state_relation'}, 'comment': "The subject is inside the object in x and y and at least partly inside it in z, not reaching below it (formula (2) of the simulated-sensor paper): e.g. a part in a parts tray or kit, a kit tray in a large box. EQ is admitted on each axis (formula (2) of the paper leaves it out, so a part exactly as tall as its kit tray, as in NIST's Goal1, would not be in it)."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_intermediate_state_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Partially-In', "inherit_condition": id.column == IntermediateStateRelation.__table__.c.id}


class Partially_In_And_In_Contact_With(IntermediateStateRelation):
    """Partially-In and touching the object from inside (tangential on some axis), e.g. a part resting on the bottom of its tray. (The literal conjunction of Partially-In and In-Contact-With is empty, since EC excludes the proper-part relations on each axis.)

    Class <https://w3id.org/kitkb/soap#Partially-In-And-In-Contact-With>.
    """

    __tablename__ = 'soap_partially_in_and_in_contact_with'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Partially-In-And-In-Contact-With', 'parent': 'soap_intermediate_state_relation'}, 'comment': 'Partially-In and touching the object from inside (tangential on some axis), e.g. a part resting on the bottom of its tray. (The literal conjunction of Partially-In and In-Contact-With is empty, since EC excludes the proper-part relations on each axis.)'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_intermediate_state_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Partially-In-And-In-Contact-With', "inherit_condition": id.column == IntermediateStateRelation.__table__.c.id}


class Under(IntermediateStateRelation):
    """The subject is below the object with overlapping footprints.

    Class <https://w3id.org/kitkb/soap#Under>.
    """

    __tablename__ = 'soap_under'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Under', 'parent': 'soap_intermediate_state_relation'}, 'comment': 'The subject is below the object with overlapping footprints.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_intermediate_state_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Under', "inherit_condition": id.column == IntermediateStateRelation.__table__.c.id}


class Under_With_Contact(IntermediateStateRelation):
    """Under and touching in z: the subject supports the object.

    Class <https://w3id.org/kitkb/soap#Under-With-Contact>.
    """

    __tablename__ = 'soap_under_with_contact'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Under-With-Contact', 'parent': 'soap_intermediate_state_relation'}, 'comment': 'Under and touching in z: the subject supports the object.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_intermediate_state_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Under-With-Contact', "inherit_condition": id.column == IntermediateStateRelation.__table__.c.id}


class X_DC(RCC8Relation):
    """Along x: disconnected: the two extents do not meet.

    Class <https://w3id.org/kitkb/soap#X-DC>.
    """

    __tablename__ = 'soap_x_dc'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#X-DC', 'parent': 'soap_rcc8_relation'}, 'comment': 'Along x: disconnected: the two extents do not meet.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#X-DC', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class X_EC(RCC8Relation):
    """Along x: externally connected: the extents touch at one end only.

    Class <https://w3id.org/kitkb/soap#X-EC>.
    """

    __tablename__ = 'soap_x_ec'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#X-EC', 'parent': 'soap_rcc8_relation'}, 'comment': 'Along x: externally connected: the extents touch at one end only.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#X-EC', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class X_EQ(RCC8Relation):
    """Along x: equal: the extents coincide.

    Class <https://w3id.org/kitkb/soap#X-EQ>.
    """

    __tablename__ = 'soap_x_eq'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#X-EQ', 'parent': 'soap_rcc8_relation'}, 'comment': 'Along x: equal: the extents coincide.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#X-EQ', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class X_NTPPi(RCC8Relation):
    """Along x: inverse of NTPP: the object's extent lies strictly inside the subject's.

    Class <https://w3id.org/kitkb/soap#X-NTPPi>.
    """

    __tablename__ = 'soap_x_ntp_pi'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#X-NTPPi', 'parent': 'soap_rcc8_relation'}, 'comment': "Along x: inverse of NTPP: the object's extent lies strictly inside the subject's."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#X-NTPPi', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class X_NTPP(RCC8Relation):
    """Along x: non-tangential proper part: the subject's extent lies strictly inside the object's.

    Class <https://w3id.org/kitkb/soap#X-NTPP>.
    """

    __tablename__ = 'soap_x_ntpp'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#X-NTPP', 'parent': 'soap_rcc8_relation'}, 'comment': "Along x: non-tangential proper part: the subject's extent lies strictly inside the object's."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#X-NTPP', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class X_PO(RCC8Relation):
    """Along x: partially overlapping: the extents share an inner part, neither contains the other.

    Class <https://w3id.org/kitkb/soap#X-PO>.
    """

    __tablename__ = 'soap_x_po'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#X-PO', 'parent': 'soap_rcc8_relation'}, 'comment': 'Along x: partially overlapping: the extents share an inner part, neither contains the other.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#X-PO', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class X_TPPi(RCC8Relation):
    """Along x: inverse of TPP: the object's extent lies inside the subject's and shares one end.

    Class <https://w3id.org/kitkb/soap#X-TPPi>.
    """

    __tablename__ = 'soap_x_tp_pi'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#X-TPPi', 'parent': 'soap_rcc8_relation'}, 'comment': "Along x: inverse of TPP: the object's extent lies inside the subject's and shares one end."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#X-TPPi', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class X_TPP(RCC8Relation):
    """Along x: tangential proper part: the subject's extent lies inside the object's and shares one end with it.

    Class <https://w3id.org/kitkb/soap#X-TPP>.
    """

    __tablename__ = 'soap_x_tpp'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#X-TPP', 'parent': 'soap_rcc8_relation'}, 'comment': "Along x: tangential proper part: the subject's extent lies inside the object's and shares one end with it."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#X-TPP', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class Y_DC(RCC8Relation):
    """Along y: disconnected: the two extents do not meet.

    Class <https://w3id.org/kitkb/soap#Y-DC>.
    """

    __tablename__ = 'soap_y_dc'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Y-DC', 'parent': 'soap_rcc8_relation'}, 'comment': 'Along y: disconnected: the two extents do not meet.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Y-DC', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class Y_EC(RCC8Relation):
    """Along y: externally connected: the extents touch at one end only.

    Class <https://w3id.org/kitkb/soap#Y-EC>.
    """

    __tablename__ = 'soap_y_ec'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Y-EC', 'parent': 'soap_rcc8_relation'}, 'comment': 'Along y: externally connected: the extents touch at one end only.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Y-EC', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class Y_EQ(RCC8Relation):
    """Along y: equal: the extents coincide.

    Class <https://w3id.org/kitkb/soap#Y-EQ>.
    """

    __tablename__ = 'soap_y_eq'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Y-EQ', 'parent': 'soap_rcc8_relation'}, 'comment': 'Along y: equal: the extents coincide.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Y-EQ', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class Y_NTPPi(RCC8Relation):
    """Along y: inverse of NTPP: the object's extent lies strictly inside the subject's.

    Class <https://w3id.org/kitkb/soap#Y-NTPPi>.
    """

    __tablename__ = 'soap_y_ntp_pi'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Y-NTPPi', 'parent': 'soap_rcc8_relation'}, 'comment': "Along y: inverse of NTPP: the object's extent lies strictly inside the subject's."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Y-NTPPi', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class Y_NTPP(RCC8Relation):
    """Along y: non-tangential proper part: the subject's extent lies strictly inside the object's.

    Class <https://w3id.org/kitkb/soap#Y-NTPP>.
    """

    __tablename__ = 'soap_y_ntpp'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Y-NTPP', 'parent': 'soap_rcc8_relation'}, 'comment': "Along y: non-tangential proper part: the subject's extent lies strictly inside the object's."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Y-NTPP', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class Y_PO(RCC8Relation):
    """Along y: partially overlapping: the extents share an inner part, neither contains the other.

    Class <https://w3id.org/kitkb/soap#Y-PO>.
    """

    __tablename__ = 'soap_y_po'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Y-PO', 'parent': 'soap_rcc8_relation'}, 'comment': 'Along y: partially overlapping: the extents share an inner part, neither contains the other.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Y-PO', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class Y_TPPi(RCC8Relation):
    """Along y: inverse of TPP: the object's extent lies inside the subject's and shares one end.

    Class <https://w3id.org/kitkb/soap#Y-TPPi>.
    """

    __tablename__ = 'soap_y_tp_pi'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Y-TPPi', 'parent': 'soap_rcc8_relation'}, 'comment': "Along y: inverse of TPP: the object's extent lies inside the subject's and shares one end."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Y-TPPi', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class Y_TPP(RCC8Relation):
    """Along y: tangential proper part: the subject's extent lies inside the object's and shares one end with it.

    Class <https://w3id.org/kitkb/soap#Y-TPP>.
    """

    __tablename__ = 'soap_y_tpp'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Y-TPP', 'parent': 'soap_rcc8_relation'}, 'comment': "Along y: tangential proper part: the subject's extent lies inside the object's and shares one end with it."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Y-TPP', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class Z_DC(RCC8Relation):
    """Along z: disconnected: the two extents do not meet.

    Class <https://w3id.org/kitkb/soap#Z-DC>.
    """

    __tablename__ = 'soap_z_dc'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Z-DC', 'parent': 'soap_rcc8_relation'}, 'comment': 'Along z: disconnected: the two extents do not meet.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Z-DC', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class Z_EC(RCC8Relation):
    """Along z: externally connected: the extents touch at one end only.

    Class <https://w3id.org/kitkb/soap#Z-EC>.
    """

    __tablename__ = 'soap_z_ec'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Z-EC', 'parent': 'soap_rcc8_relation'}, 'comment': 'Along z: externally connected: the extents touch at one end only.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Z-EC', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class Z_EQ(RCC8Relation):
    """Along z: equal: the extents coincide.

    Class <https://w3id.org/kitkb/soap#Z-EQ>.
    """

    __tablename__ = 'soap_z_eq'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Z-EQ', 'parent': 'soap_rcc8_relation'}, 'comment': 'Along z: equal: the extents coincide.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Z-EQ', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class Z_NTPPi(RCC8Relation):
    """Along z: inverse of NTPP: the object's extent lies strictly inside the subject's.

    Class <https://w3id.org/kitkb/soap#Z-NTPPi>.
    """

    __tablename__ = 'soap_z_ntp_pi'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Z-NTPPi', 'parent': 'soap_rcc8_relation'}, 'comment': "Along z: inverse of NTPP: the object's extent lies strictly inside the subject's."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Z-NTPPi', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class Z_NTPP(RCC8Relation):
    """Along z: non-tangential proper part: the subject's extent lies strictly inside the object's.

    Class <https://w3id.org/kitkb/soap#Z-NTPP>.
    """

    __tablename__ = 'soap_z_ntpp'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Z-NTPP', 'parent': 'soap_rcc8_relation'}, 'comment': "Along z: non-tangential proper part: the subject's extent lies strictly inside the object's."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Z-NTPP', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class Z_PO(RCC8Relation):
    """Along z: partially overlapping: the extents share an inner part, neither contains the other.

    Class <https://w3id.org/kitkb/soap#Z-PO>.
    """

    __tablename__ = 'soap_z_po'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Z-PO', 'parent': 'soap_rcc8_relation'}, 'comment': 'Along z: partially overlapping: the extents share an inner part, neither contains the other.'}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Z-PO', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class Z_TPPi(RCC8Relation):
    """Along z: inverse of TPP: the object's extent lies inside the subject's and shares one end.

    Class <https://w3id.org/kitkb/soap#Z-TPPi>.
    """

    __tablename__ = 'soap_z_tp_pi'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Z-TPPi', 'parent': 'soap_rcc8_relation'}, 'comment': "Along z: inverse of TPP: the object's extent lies inside the subject's and shares one end."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Z-TPPi', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class Z_TPP(RCC8Relation):
    """Along z: tangential proper part: the subject's extent lies inside the object's and shares one end with it.

    Class <https://w3id.org/kitkb/soap#Z-TPP>.
    """

    __tablename__ = 'soap_z_tpp'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/soap#Z-TPP', 'parent': 'soap_rcc8_relation'}, 'comment': "Along z: tangential proper part: the subject's extent lies inside the object's and shares one end with it."}

    id: Mapped[int] = mapped_column(ForeignKey('soap_rcc8_relation.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/soap#Z-TPP', "inherit_condition": id.column == RCC8Relation.__table__.c.id}


class PoseLocationIn(PoseLocation):
    """A pose location whose object is also inside its reference object.

    Class <https://w3id.org/kitkb/kitting#PoseLocationIn>.
    """

    __tablename__ = 'ktw_pose_location_in'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#PoseLocationIn', 'parent': 'ktw_pose_location'}, 'comment': 'A pose location whose object is also inside its reference object.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_pose_location.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#PoseLocationIn', "inherit_condition": id.column == PoseLocation.__table__.c.id}


class PoseLocationOn(PoseLocation):
    """A pose location whose object also rests on top of its reference object.

    Class <https://w3id.org/kitkb/kitting#PoseLocationOn>.
    """

    __tablename__ = 'ktw_pose_location_on'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#PoseLocationOn', 'parent': 'ktw_pose_location'}, 'comment': 'A pose location whose object also rests on top of its reference object.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_pose_location.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#PoseLocationOn', "inherit_condition": id.column == PoseLocation.__table__.c.id}


class PoseOnlyLocation(PoseLocation):
    """A pose location with no in/on relation implied.

    Class <https://w3id.org/kitkb/kitting#PoseOnlyLocation>.
    """

    __tablename__ = 'ktw_pose_only_location'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#PoseOnlyLocation', 'parent': 'ktw_pose_location'}, 'comment': 'A pose location with no in/on relation implied.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_pose_location.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#PoseOnlyLocation', "inherit_condition": id.column == PoseLocation.__table__.c.id}


class RelativeLocationIn(RelativeLocation):
    """A relative location stating that the object is inside its reference object.

    Class <https://w3id.org/kitkb/kitting#RelativeLocationIn>.
    """

    __tablename__ = 'ktw_relative_location_in'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#RelativeLocationIn', 'parent': 'ktw_relative_location'}, 'comment': 'A relative location stating that the object is inside its reference object.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_relative_location.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#RelativeLocationIn', "inherit_condition": id.column == RelativeLocation.__table__.c.id}


class RelativeLocationOn(RelativeLocation):
    """A relative location stating that the object is on top of its reference object.

    Class <https://w3id.org/kitkb/kitting#RelativeLocationOn>.
    """

    __tablename__ = 'ktw_relative_location_on'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#RelativeLocationOn', 'parent': 'ktw_relative_location'}, 'comment': 'A relative location stating that the object is on top of its reference object.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_relative_location.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#RelativeLocationOn', "inherit_condition": id.column == RelativeLocation.__table__.c.id}


class BoxyShape(InternalShape):
    """A box shape of given length (longer horizontal side), width and height, open or closed on top; its frame sits in the middle of the bottom with z pointing up into the box and x along the length.

    Class <https://w3id.org/kitkb/kitting#BoxyShape>.
    """

    __tablename__ = 'ktw_boxy_shape'
    __table_args__ = (
        CheckConstraint(column('height') > literal(0.0), name='height_gt_0'),
        CheckConstraint(column('length') > literal(0.0), name='length_gt_0'),
        CheckConstraint(column('width') > literal(0.0), name='width_gt_0'),
        {'info': {'iri': 'https://w3id.org/kitkb/kitting#BoxyShape', 'parent': 'ktw_internal_shape'}, 'comment': 'A box shape of given length (longer horizontal side), width and height, open or closed on top; its frame sits in the middle of the bottom with z pointing up into the box and x along the length.'},
    )

    id: Mapped[int] = mapped_column(ForeignKey('ktw_internal_shape.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#BoxyShape', "inherit_condition": id.column == InternalShape.__table__.c.id}
    has_top: Mapped[bool] = mapped_column(Boolean(), nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasBoxyShape_HasTop', 'kind': 'data', 'value': 'boolean', 'datatype': 'http://www.w3.org/2001/XMLSchema#boolean'})
    height: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasBoxyShape_Height', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    length: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasBoxyShape_Length', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    width: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasBoxyShape_Width', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})


class CylindricalShape(InternalShape):
    """A right circular cylinder shape of given diameter and height, open or closed on top; its frame sits in the middle of the bottom with z along the axis.

    Class <https://w3id.org/kitkb/kitting#CylindricalShape>.
    """

    __tablename__ = 'ktw_cylindrical_shape'
    __table_args__ = (
        CheckConstraint(column('diameter') > literal(0.0), name='diameter_gt_0'),
        CheckConstraint(column('height') > literal(0.0), name='height_gt_0'),
        {'info': {'iri': 'https://w3id.org/kitkb/kitting#CylindricalShape', 'parent': 'ktw_internal_shape'}, 'comment': 'A right circular cylinder shape of given diameter and height, open or closed on top; its frame sits in the middle of the bottom with z along the axis.'},
    )

    id: Mapped[int] = mapped_column(ForeignKey('ktw_internal_shape.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#CylindricalShape', "inherit_condition": id.column == InternalShape.__table__.c.id}
    diameter: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasCylindricalShape_Diameter', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    has_top: Mapped[bool] = mapped_column(Boolean(), nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasCylindricalShape_HasTop', 'kind': 'data', 'value': 'boolean', 'datatype': 'http://www.w3.org/2001/XMLSchema#boolean'})
    height: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasCylindricalShape_Height', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})


class GripperEffector(EndEffector):
    """An end effector that holds objects by closing fingers or jaws on them.

    Class <https://w3id.org/kitkb/kitting#GripperEffector>.
    """

    __tablename__ = 'ktw_gripper_effector'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#GripperEffector', 'parent': 'ktw_end_effector'}, 'comment': 'An end effector that holds objects by closing fingers or jaws on them.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_end_effector.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#GripperEffector', "inherit_condition": id.column == EndEffector.__table__.c.id}


class VacuumEffector(EndEffector):
    """Abstract: an end effector that holds objects by suction through one or more cups.

    Class <https://w3id.org/kitkb/kitting#VacuumEffector>.
    """

    __tablename__ = 'ktw_vacuum_effector'
    __table_args__ = (
        CheckConstraint(column('cup_diameter') > literal(0.0), name='cup_diameter_gt_0'),
        CheckConstraint(column('length') > literal(0.0), name='length_gt_0'),
        {'info': {'iri': 'https://w3id.org/kitkb/kitting#VacuumEffector', 'parent': 'ktw_end_effector'}, 'comment': 'Abstract: an end effector that holds objects by suction through one or more cups.'},
    )

    id: Mapped[int] = mapped_column(ForeignKey('ktw_end_effector.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#VacuumEffector', "inherit_condition": id.column == EndEffector.__table__.c.id}
    cup_diameter: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasVacuumEffector_CupDiameter', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})
    length: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasVacuumEffector_Length', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})


class PartsBin(PartsVessel):
    """A parts vessel in which parts lie loosely. Fig. 1 places it under BoxyObject; kitkb follows NIST (PartsVessel).

    Class <https://w3id.org/kitkb/kitting#PartsBin>.
    """

    __tablename__ = 'ktw_parts_bin'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#PartsBin', 'parent': 'ktw_parts_vessel'}, 'comment': 'A parts vessel in which parts lie loosely. Fig. 1 places it under BoxyObject; kitkb follows NIST (PartsVessel).'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_parts_vessel.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#PartsBin', "inherit_condition": id.column == PartsVessel.__table__.c.id}


class PartsTray(PartsVessel):
    """A parts vessel in which parts sit at fixed places. Fig. 1 places it under BoxyObject; kitkb follows NIST (PartsVessel).

    Class <https://w3id.org/kitkb/kitting#PartsTray>.
    """

    __tablename__ = 'ktw_parts_tray'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#PartsTray', 'parent': 'ktw_parts_vessel'}, 'comment': 'A parts vessel in which parts sit at fixed places. Fig. 1 places it under BoxyObject; kitkb follows NIST (PartsVessel).'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_parts_vessel.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#PartsTray', "inherit_condition": id.column == PartsVessel.__table__.c.id}


class VacuumEffectorMultiCup(VacuumEffector):
    """A vacuum end effector with several equal cups laid out on a circle.

    Class <https://w3id.org/kitkb/kitting#VacuumEffectorMultiCup>.
    """

    __tablename__ = 'ktw_vacuum_effector_multi_cup'
    __table_args__ = (
        CheckConstraint(column('array_number') > literal(0), name='array_number_gt_0'),
        CheckConstraint(column('array_radius') > literal(0.0), name='array_radius_gt_0'),
        {'info': {'iri': 'https://w3id.org/kitkb/kitting#VacuumEffectorMultiCup', 'parent': 'ktw_vacuum_effector'}, 'comment': 'A vacuum end effector with several equal cups laid out on a circle.'},
    )

    id: Mapped[int] = mapped_column(ForeignKey('ktw_vacuum_effector.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#VacuumEffectorMultiCup', "inherit_condition": id.column == VacuumEffector.__table__.c.id}
    array_number: Mapped[int] = mapped_column(Integer(), nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasVacuumEffectorMultiCup_ArrayNumber', 'kind': 'data', 'value': 'integer', 'datatype': 'http://www.w3.org/2001/XMLSchema#positiveInteger'})
    array_radius: Mapped[float] = mapped_column(_DECIMAL, nullable=False, info={'iri': 'https://w3id.org/kitkb/kitting#hasVacuumEffectorMultiCup_ArrayRadius', 'kind': 'data', 'value': 'decimal', 'datatype': 'http://www.w3.org/2001/XMLSchema#decimal'})


class VacuumEffectorSingleCup(VacuumEffector):
    """A vacuum end effector with a single cup.

    Class <https://w3id.org/kitkb/kitting#VacuumEffectorSingleCup>.
    """

    __tablename__ = 'ktw_vacuum_effector_single_cup'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#VacuumEffectorSingleCup', 'parent': 'ktw_vacuum_effector'}, 'comment': 'A vacuum end effector with a single cup.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_vacuum_effector.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#VacuumEffectorSingleCup', "inherit_condition": id.column == VacuumEffector.__table__.c.id}


class PartsTrayWithParts(PartsTray):
    """A parts tray that holds at least one part (Fig. 1 and Fig. 7 of the kit-building paper). The NIST OWL model has no such class: there a PartsTray holds its parts directly through hasPartsVessel_Part. kitkb therefore keeps it as a subclass of PartsTray restricted to at least one Part.

    Class <https://w3id.org/kitkb/kitting#PartsTrayWithParts>.
    """

    __tablename__ = 'ktw_parts_tray_with_parts'
    __table_args__ = {'info': {'iri': 'https://w3id.org/kitkb/kitting#PartsTrayWithParts', 'parent': 'ktw_parts_tray'}, 'comment': 'A parts tray that holds at least one part (Fig. 1 and Fig. 7 of the kit-building paper). The NIST OWL model has no such class: there a PartsTray holds its parts directly through hasPartsVessel_Part. kitkb therefore keeps it as a subclass of PartsTray restricted to at least one Part.'}

    id: Mapped[int] = mapped_column(ForeignKey('ktw_parts_tray.id', deferrable=True, initially="DEFERRED"), primary_key=True, autoincrement=False)
    __mapper_args__ = {"polymorphic_identity": 'https://w3id.org/kitkb/kitting#PartsTrayWithParts', "inherit_condition": id.column == PartsTray.__table__.c.id}


#: Generated class of each table name.
CLASSES: dict[str, type[Base]] = {
    'kitkb_thing': Thing,
    'ktw_data_thing': DataThing,
    'ktw_solid_object': SolidObject,
    'soap_action': Action,
    'soap_action_failure': ActionFailure,
    'soap_action_program': ActionProgram,
    'soap_check_phase': CheckPhase,
    'soap_command_step': CommandStep,
    'soap_consequence_kind': ConsequenceKind,
    'soap_effect': Effect,
    'soap_execution_policy': ExecutionPolicy,
    'soap_failure_mode': FailureMode,
    'soap_failure_remediation': FailureRemediation,
    'soap_fault_kind': FaultKind,
    'soap_fault_mechanism': FaultMechanism,
    'soap_formula': Formula,
    'soap_function': Function,
    'soap_function_comparison': FunctionComparison,
    'soap_function_term': FunctionTerm,
    'soap_notification': Notification,
    'soap_numeric_effect': NumericEffect,
    'soap_numeric_expression': NumericExpression,
    'soap_object_consequence': ObjectConsequence,
    'soap_parameter_binding': ParameterBinding,
    'soap_partial_kit_policy': PartialKitPolicy,
    'soap_precondition': Precondition,
    'soap_predicate': Predicate,
    'soap_recovery_plan': RecoveryPlan,
    'soap_recovery_step': RecoveryStep,
    'soap_recovery_strategy': RecoveryStrategy,
    'soap_spatial_relation': SpatialRelation,
    'soap_term': Term,
    'ktw_box_volume': BoxVolume,
    'ktw_kit_design': KitDesign,
    'ktw_part_ref_and_pose': PartRefAndPose,
    'ktw_physical_location': PhysicalLocation,
    'ktw_point': Point,
    'ktw_pose_sensor': PoseSensor,
    'ktw_shape_design': ShapeDesign,
    'ktw_slot': Slot,
    'ktw_stock_keeping_unit': StockKeepingUnit,
    'ktw_vector': Vector,
    'ktw_boxy_object': BoxyObject,
    'ktw_no_sku_object': NoSkuObject,
    'ktw_sku_object': SkuObject,
    'soap_atom': Atom,
    'soap_conjunction': Conjunction,
    'soap_disjunction': Disjunction,
    'soap_existential': Existential,
    'soap_negation': Negation,
    'soap_function_to_decimal': FunctionToDecimal,
    'soap_function_to_function': FunctionToFunction,
    'soap_assign_effect': AssignEffect,
    'soap_decrease_effect': DecreaseEffect,
    'soap_increase_effect': IncreaseEffect,
    'soap_count_expression': CountExpression,
    'soap_design_count_expression': DesignCountExpression,
    'soap_cardinal_direction_relation': CardinalDirectionRelation,
    'soap_intermediate_state_relation': IntermediateStateRelation,
    'soap_rcc8_relation': RCC8Relation,
    'soap_parameter': Parameter,
    'soap_variable': Variable,
    'ktw_pose_location': PoseLocation,
    'ktw_relative_location': RelativeLocation,
    'ktw_external_shape': ExternalShape,
    'ktw_internal_shape': InternalShape,
    'ktw_end_effector': EndEffector,
    'ktw_end_effector_changing_station': EndEffectorChangingStation,
    'ktw_end_effector_holder': EndEffectorHolder,
    'ktw_human': Human,
    'ktw_kit': Kit,
    'ktw_kitting_workstation': KittingWorkstation,
    'ktw_large_box_with_empty_kit_trays': LargeBoxWithEmptyKitTrays,
    'ktw_large_box_with_kits': LargeBoxWithKits,
    'ktw_mechanical_component': MechanicalComponent,
    'ktw_robot': Robot,
    'ktw_work_table': WorkTable,
    'ktw_kit_tray': KitTray,
    'ktw_large_container': LargeContainer,
    'ktw_part': Part,
    'ktw_parts_vessel': PartsVessel,
    'soap_count_atom': CountAtom,
    'soap_model_atom': ModelAtom,
    'soap_predicate_atom': PredicateAtom,
    'soap_relation_atom': RelationAtom,
    'soap_sensor_atom': SensorAtom,
    'soap_sku_atom': SkuAtom,
    'soap_function_to_decimal_equal': FunctionToDecimalEqual,
    'soap_function_to_decimal_greater': FunctionToDecimalGreater,
    'soap_function_to_decimal_greater_or_equal': FunctionToDecimalGreaterOrEqual,
    'soap_function_to_decimal_less': FunctionToDecimalLess,
    'soap_function_to_decimal_less_or_equal': FunctionToDecimalLessOrEqual,
    'soap_function_to_function_equal': FunctionToFunctionEqual,
    'soap_function_to_function_greater': FunctionToFunctionGreater,
    'soap_function_to_function_greater_or_equal': FunctionToFunctionGreaterOrEqual,
    'soap_function_to_function_less': FunctionToFunctionLess,
    'soap_function_to_function_less_or_equal': FunctionToFunctionLessOrEqual,
    'soap_x_minus': X_Minus,
    'soap_x_plus': X_Plus,
    'soap_y_minus': Y_Minus,
    'soap_y_plus': Y_Plus,
    'soap_z_minus': Z_Minus,
    'soap_z_plus': Z_Plus,
    'soap_contained_in': Contained_In,
    'soap_in_contact_with': In_Contact_With,
    'soap_in_or_against': In_Or_Against,
    'soap_not_contained_in': Not_Contained_In,
    'soap_not_in_contact_with': Not_In_Contact_With,
    'soap_on_top_of': On_Top_Of,
    'soap_on_top_with_contact': On_Top_With_Contact,
    'soap_partially_in': Partially_In,
    'soap_partially_in_and_in_contact_with': Partially_In_And_In_Contact_With,
    'soap_under': Under,
    'soap_under_with_contact': Under_With_Contact,
    'soap_x_dc': X_DC,
    'soap_x_ec': X_EC,
    'soap_x_eq': X_EQ,
    'soap_x_ntp_pi': X_NTPPi,
    'soap_x_ntpp': X_NTPP,
    'soap_x_po': X_PO,
    'soap_x_tp_pi': X_TPPi,
    'soap_x_tpp': X_TPP,
    'soap_y_dc': Y_DC,
    'soap_y_ec': Y_EC,
    'soap_y_eq': Y_EQ,
    'soap_y_ntp_pi': Y_NTPPi,
    'soap_y_ntpp': Y_NTPP,
    'soap_y_po': Y_PO,
    'soap_y_tp_pi': Y_TPPi,
    'soap_y_tpp': Y_TPP,
    'soap_z_dc': Z_DC,
    'soap_z_ec': Z_EC,
    'soap_z_eq': Z_EQ,
    'soap_z_ntp_pi': Z_NTPPi,
    'soap_z_ntpp': Z_NTPP,
    'soap_z_po': Z_PO,
    'soap_z_tp_pi': Z_TPPi,
    'soap_z_tpp': Z_TPP,
    'ktw_pose_location_in': PoseLocationIn,
    'ktw_pose_location_on': PoseLocationOn,
    'ktw_pose_only_location': PoseOnlyLocation,
    'ktw_relative_location_in': RelativeLocationIn,
    'ktw_relative_location_on': RelativeLocationOn,
    'ktw_boxy_shape': BoxyShape,
    'ktw_cylindrical_shape': CylindricalShape,
    'ktw_gripper_effector': GripperEffector,
    'ktw_vacuum_effector': VacuumEffector,
    'ktw_parts_bin': PartsBin,
    'ktw_parts_tray': PartsTray,
    'ktw_vacuum_effector_multi_cup': VacuumEffectorMultiCup,
    'ktw_vacuum_effector_single_cup': VacuumEffectorSingleCup,
    'ktw_parts_tray_with_parts': PartsTrayWithParts,
}
