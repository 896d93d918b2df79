; kitkb PDDL problem (strips encoding), generated with unified-planning's PDDLWriter
; from the initial state kit-a2b3c3d1e1/init.ttl
; and the goal state kit-a2b3c3d1e1/goal.ttl.
(define (problem kitting-problem)
 (:domain kitting-domain)
 ; object changing_station_1: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#changing_station_1>
 ; object empty_kit_tray_supply: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#empty_kit_tray_supply>
 ; object finished_kit_receiver_1: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#finished_kit_receiver_1>
 ; object kit_1: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#kit_1>
 ; object kit_tray_1: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#kit_tray_1>
 ; object part_a_1: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_a_1>
 ; object part_a_2: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_a_2>
 ; object part_a_3: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_a_3>
 ; object part_a_tray: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_a_tray>
 ; object part_b_1: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_b_1>
 ; object part_b_2: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_b_2>
 ; object part_b_3: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_b_3>
 ; object part_b_4: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_b_4>
 ; object part_b_tray: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_b_tray>
 ; object part_c_1: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_c_1>
 ; object part_c_2: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_c_2>
 ; object part_c_3: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_c_3>
 ; object part_c_4: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_c_4>
 ; object part_c_tray: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_c_tray>
 ; object part_d_1: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_d_1>
 ; object part_d_2: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_d_2>
 ; object part_d_tray: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_d_tray>
 ; object part_e_1: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_e_1>
 ; object part_e_2: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_e_2>
 ; object part_e_tray: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_e_tray>
 ; object part_gripper: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_gripper>
 ; object part_gripper_holder: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#part_gripper_holder>
 ; object parts_table_1: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#parts_table_1>
 ; object robot_1: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#robot_1>
 ; object sku_empty_kit_tray_box: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#sku_empty_kit_tray_box>
 ; object sku_finished_kit_box: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#sku_finished_kit_box>
 ; object sku_kit_tray: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#sku_kit_tray>
 ; object sku_part_a: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#sku_part_a>
 ; object sku_part_b: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#sku_part_b>
 ; object sku_part_c: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#sku_part_c>
 ; object sku_part_d: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#sku_part_d>
 ; object sku_part_e: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#sku_part_e>
 ; object sku_parts_tray: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#sku_parts_tray>
 ; object tray_gripper: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#tray_gripper>
 ; object tray_gripper_holder: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#tray_gripper_holder>
 ; object work_table_1: <https://w3id.org/kitkb/scenario/kit-a2b3c3d1e1#work_table_1>
 (:objects
   part_gripper tray_gripper - endeffector
   part_gripper_holder tray_gripper_holder - endeffectorholder
   changing_station_1 - endeffectorchangingstation
   robot_1 - robot
   kit_1 - kit
   kit_tray_1 - kittray
   parts_table_1 work_table_1 - worktable
   part_a_1 part_a_2 part_a_3 part_b_1 part_b_2 part_b_3 part_b_4 part_c_1 part_c_2 part_c_3 part_c_4 part_d_1 part_d_2 part_e_1 part_e_2 - part
   part_a_tray part_b_tray part_c_tray part_d_tray part_e_tray - partstray
   finished_kit_receiver_1 - largeboxwithkits
   sku_empty_kit_tray_box sku_finished_kit_box sku_kit_tray sku_part_a sku_part_b sku_part_c sku_part_d sku_part_e sku_parts_tray - stockkeepingunit
   empty_kit_tray_supply - largeboxwithemptykittrays
 )
 (:init
              (endeffector-location-endeffectorholder part_gripper part_gripper_holder)
              (endeffector-location-endeffectorholder tray_gripper tray_gripper_holder)
              (endeffector-type-kit tray_gripper kit_1)
              (endeffector-type-kittray tray_gripper kit_tray_1)
              (endeffector-type-part part_gripper part_a_1)
              (endeffector-type-part part_gripper part_a_2)
              (endeffector-type-part part_gripper part_a_3)
              (endeffector-type-part part_gripper part_b_1)
              (endeffector-type-part part_gripper part_b_2)
              (endeffector-type-part part_gripper part_b_3)
              (endeffector-type-part part_gripper part_b_4)
              (endeffector-type-part part_gripper part_c_1)
              (endeffector-type-part part_gripper part_c_2)
              (endeffector-type-part part_gripper part_c_3)
              (endeffector-type-part part_gripper part_c_4)
              (endeffector-type-part part_gripper part_d_1)
              (endeffector-type-part part_gripper part_d_2)
              (endeffector-type-part part_gripper part_e_1)
              (endeffector-type-part part_gripper part_e_2)
              (endeffectorholder-location-changingstation part_gripper_holder changing_station_1)
              (endeffectorholder-location-changingstation tray_gripper_holder changing_station_1)
              (kit-kittray kit_1 kit_tray_1)
              (kittray-location-lbwekt kit_tray_1 empty_kit_tray_supply)
              (lbwk-not-full finished_kit_receiver_1)
              (part-location-partstray part_a_1 part_a_tray)
              (part-location-partstray part_a_2 part_a_tray)
              (part-location-partstray part_a_3 part_a_tray)
              (part-location-partstray part_b_1 part_b_tray)
              (part-location-partstray part_b_2 part_b_tray)
              (part-location-partstray part_b_3 part_b_tray)
              (part-location-partstray part_b_4 part_b_tray)
              (part-location-partstray part_c_1 part_c_tray)
              (part-location-partstray part_c_2 part_c_tray)
              (part-location-partstray part_c_3 part_c_tray)
              (part-location-partstray part_c_4 part_c_tray)
              (part-location-partstray part_d_1 part_d_tray)
              (part-location-partstray part_d_2 part_d_tray)
              (part-location-partstray part_e_1 part_e_tray)
              (part-location-partstray part_e_2 part_e_tray)
              (part-sku part_a_1 sku_part_a)
              (part-sku part_a_2 sku_part_a)
              (part-sku part_a_3 sku_part_a)
              (part-sku part_b_1 sku_part_b)
              (part-sku part_b_2 sku_part_b)
              (part-sku part_b_3 sku_part_b)
              (part-sku part_b_4 sku_part_b)
              (part-sku part_c_1 sku_part_c)
              (part-sku part_c_2 sku_part_c)
              (part-sku part_c_3 sku_part_c)
              (part-sku part_c_4 sku_part_c)
              (part-sku part_d_1 sku_part_d)
              (part-sku part_d_2 sku_part_d)
              (part-sku part_e_1 sku_part_e)
              (part-sku part_e_2 sku_part_e)
              (partstray-not-empty part_a_tray)
              (partstray-not-empty part_b_tray)
              (partstray-not-empty part_c_tray)
              (partstray-not-empty part_d_tray)
              (partstray-not-empty part_e_tray)
              (quantity-kit-pending kit_1 sku_part_a part_a_1)
              (quantity-kit-pending kit_1 sku_part_a part_a_2)
              (quantity-kit-pending kit_1 sku_part_b part_b_1)
              (quantity-kit-pending kit_1 sku_part_b part_b_2)
              (quantity-kit-pending kit_1 sku_part_b part_b_3)
              (quantity-kit-pending kit_1 sku_part_c part_c_1)
              (quantity-kit-pending kit_1 sku_part_c part_c_2)
              (quantity-kit-pending kit_1 sku_part_c part_c_3)
              (quantity-kit-pending kit_1 sku_part_d part_d_1)
              (quantity-kit-pending kit_1 sku_part_e part_e_1)
              (robot-with-no-endeffector robot_1)
              (worktable-empty work_table_1)
 )
 (:goal (and 
           (endeffector-location-endeffectorholder part_gripper part_gripper_holder)
           (endeffector-location-endeffectorholder tray_gripper tray_gripper_holder)
           (kit-location-lbwk kit_1 finished_kit_receiver_1)
           (robot-with-no-endeffector robot_1)
           (worktable-empty work_table_1)
           (quantity-kit-counted kit_1 sku_part_a part_a_1)
           (quantity-kit-counted kit_1 sku_part_a part_a_2)
           (quantity-kit-counted kit_1 sku_part_b part_b_1)
           (quantity-kit-counted kit_1 sku_part_b part_b_2)
           (quantity-kit-counted kit_1 sku_part_b part_b_3)
           (quantity-kit-counted kit_1 sku_part_c part_c_1)
           (quantity-kit-counted kit_1 sku_part_c part_c_2)
           (quantity-kit-counted kit_1 sku_part_c part_c_3)
           (quantity-kit-counted kit_1 sku_part_d part_d_1)
           (quantity-kit-counted kit_1 sku_part_e part_e_1)
        )
 )
)
