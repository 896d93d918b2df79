; kitkb PDDL domain (strips encoding), generated from the SOAP instances
; of <https://w3id.org/kitkb/kitting-domain> with unified-planning's PDDLWriter.
; Counts are compiled into token objects (see kb/planning/strips.py).
(define (domain kitting-domain)
 (:requirements :strips :typing)
; type datathing: <https://w3id.org/kitkb/kitting#DataThing>
; type endeffector: <https://w3id.org/kitkb/kitting#EndEffector>
; type endeffectorchangingstation: <https://w3id.org/kitkb/kitting#EndEffectorChangingStation>
; type endeffectorholder: <https://w3id.org/kitkb/kitting#EndEffectorHolder>
; type kit: <https://w3id.org/kitkb/kitting#Kit>
; type kittray: <https://w3id.org/kitkb/kitting#KitTray>
; type largeboxwithemptykittrays: <https://w3id.org/kitkb/kitting#LargeBoxWithEmptyKitTrays>
; type largeboxwithkits: <https://w3id.org/kitkb/kitting#LargeBoxWithKits>
; type largecontainer: <https://w3id.org/kitkb/kitting#LargeContainer>
; type noskuobject: <https://w3id.org/kitkb/kitting#NoSkuObject>
; type part: <https://w3id.org/kitkb/kitting#Part>
; type partstray: <https://w3id.org/kitkb/kitting#PartsTray>
; type partsvessel: <https://w3id.org/kitkb/kitting#PartsVessel>
; type rejectbin: <https://w3id.org/kitkb/kitting-domain#RejectBin>
; type robot: <https://w3id.org/kitkb/kitting#Robot>
; type skuobject: <https://w3id.org/kitkb/kitting#SkuObject>
; type solidobject: <https://w3id.org/kitkb/kitting#SolidObject>
; type stockkeepingunit: <https://w3id.org/kitkb/kitting#StockKeepingUnit>
; type worktable: <https://w3id.org/kitkb/kitting#WorkTable>
 (:types
    solidobject datathing - object
    stockkeepingunit - datathing
    noskuobject skuobject - solidobject
    kittray part partsvessel largecontainer - skuobject
    rejectbin - largecontainer
    partstray - partsvessel
    endeffector endeffectorholder endeffectorchangingstation robot kit worktable largeboxwithkits largeboxwithemptykittrays - noskuobject
 )
 (:predicates 
             ; source: <https://w3id.org/kitkb/kitting-domain#endeffector-location-endeffectorholder>
             (endeffector-location-endeffectorholder ?endeffector - endeffector ?endeffectorholder - endeffectorholder)
             ; source: <https://w3id.org/kitkb/kitting-domain#endeffectorholder-location-changingstation>
             (endeffectorholder-location-changingstation ?endeffectorholder - endeffectorholder ?endeffectorchangingstation - endeffectorchangingstation)
             ; source: <https://w3id.org/kitkb/kitting-domain#robot-with-no-endeffector>
             (robot-with-no-endeffector ?robot - robot)
             ; source: <https://w3id.org/kitkb/kitting-domain#endeffector-location-robot>
             (endeffector-location-robot ?endeffector - endeffector ?robot - robot)
             ; source: <https://w3id.org/kitkb/kitting-domain#endeffectorholder-empty>
             (endeffectorholder-empty ?endeffectorholder - endeffectorholder)
             ; source: <https://w3id.org/kitkb/kitting-domain#robot-empty>
             (robot-empty ?robot - robot)
             ; source: <https://w3id.org/kitkb/kitting-domain#robot-with-endeffector>
             (robot-with-endeffector ?robot - robot ?endeffector - endeffector)
             ; source: <https://w3id.org/kitkb/kitting-domain#kit-kittray>
             (kit-kittray ?kit - kit ?kittray - kittray)
             ; source: <https://w3id.org/kitkb/kitting-domain#kittray-location-worktable>
             (kittray-location-worktable ?kittray - kittray ?worktable - worktable)
             ; source: <https://w3id.org/kitkb/kitting-domain#kit-location-worktable>
             (kit-location-worktable ?kit - kit ?worktable - worktable)
             ; source: <https://w3id.org/kitkb/kitting-domain#part-location-worktable>
             (part-location-worktable ?part - part ?worktable - worktable)
             ; source: <https://w3id.org/kitkb/kitting-domain#part-quality-ok>
             (part-quality-ok ?part - part)
             ; source: <https://w3id.org/kitkb/kitting-domain#part-location-partstray>
             (part-location-partstray ?part - part ?partstray - partstray)
             ; source: <https://w3id.org/kitkb/kitting-domain#partstray-not-empty>
             (partstray-not-empty ?partstray - partstray)
             ; source: <https://w3id.org/kitkb/kitting-domain#kit-location-robot>
             (kit-location-robot ?kit - kit ?robot - robot)
             ; source: <https://w3id.org/kitkb/kitting-domain#lbwk-not-full>
             (lbwk-not-full ?largeboxwithkits - largeboxwithkits)
             ; source: <https://w3id.org/kitkb/kitting-domain#robot-holds-kit>
             (robot-holds-kit ?robot - robot ?kit - kit)
             ; source: <https://w3id.org/kitkb/kitting-domain#kit-location-lbwk>
             (kit-location-lbwk ?kit - kit ?largeboxwithkits - largeboxwithkits)
             ; source: <https://w3id.org/kitkb/kitting-domain#kittray-location-robot>
             (kittray-location-robot ?kittray - kittray ?robot - robot)
             ; source: <https://w3id.org/kitkb/kitting-domain#robot-holds-kittray>
             (robot-holds-kittray ?robot - robot ?kittray - kittray)
             ; source: <https://w3id.org/kitkb/kitting-domain#worktable-empty>
             (worktable-empty ?worktable - worktable)
             ; source: <https://w3id.org/kitkb/kitting-domain#part-location-robot>
             (part-location-robot ?part - part ?robot - robot)
             ; source: <https://w3id.org/kitkb/kitting-domain#part-sku>
             (part-sku ?part - part ?stockkeepingunit - stockkeepingunit)
             ; source: <https://w3id.org/kitkb/kitting-domain#robot-holds-part>
             (robot-holds-part ?robot - robot ?part - part)
             ; source: <https://w3id.org/kitkb/kitting-domain#part-location-kit>
             (part-location-kit ?part - part ?kit - kit)
             ; source: <https://w3id.org/kitkb/kitting-domain#endeffector-type-part>
             (endeffector-type-part ?endeffector - endeffector ?part - part)
             ; source: <https://w3id.org/kitkb/kitting-domain#part-location-rejectbin>
             (part-location-rejectbin ?part - part ?rejectbin - rejectbin)
             ; source: <https://w3id.org/kitkb/kitting-domain#endeffector-type-kit>
             (endeffector-type-kit ?endeffector - endeffector ?kit - kit)
             ; source: <https://w3id.org/kitkb/kitting-domain#endeffector-type-kittray>
             (endeffector-type-kittray ?endeffector - endeffector ?kittray - kittray)
             ; source: <https://w3id.org/kitkb/kitting-domain#kittray-location-lbwekt>
             (kittray-location-lbwekt ?kittray - kittray ?largeboxwithemptykittrays - largeboxwithemptykittrays)
             ; source: <https://w3id.org/kitkb/kitting-domain#put-part_pre_less_quantity-kit_capacity-kit>
             (quantity-kit-pending ?kit - kit ?stockkeepingunit - stockkeepingunit ?part - part)
             ; source: <https://w3id.org/kitkb/kitting-domain#put-part_pre_less_quantity-kit_capacity-kit>
             (quantity-kit-counted ?kit - kit ?stockkeepingunit - stockkeepingunit ?part - part)
 )
 ; source: <https://w3id.org/kitkb/kitting-domain#attach-endeffector>
 (:action attach-endeffector
  :parameters ( ?robot - robot ?endeffector - endeffector ?endeffectorholder - endeffectorholder ?changingstation - endeffectorchangingstation)
  :precondition (and (endeffector-location-endeffectorholder ?endeffector ?endeffectorholder) (endeffectorholder-location-changingstation ?endeffectorholder ?changingstation) (robot-with-no-endeffector ?robot))
  :effect (and (not (endeffector-location-endeffectorholder ?endeffector ?endeffectorholder)) (not (robot-with-no-endeffector ?robot)) (endeffector-location-robot ?endeffector ?robot) (endeffectorholder-empty ?endeffectorholder) (robot-empty ?robot) (robot-with-endeffector ?robot ?endeffector)))
 ; source: <https://w3id.org/kitkb/kitting-domain#create-kit>
 (:action create-kit
  :parameters ( ?kit - kit ?kittray - kittray ?worktable - worktable)
  :precondition (and (kit-kittray ?kit ?kittray) (kittray-location-worktable ?kittray ?worktable))
  :effect (and (not (kittray-location-worktable ?kittray ?worktable)) (kit-location-worktable ?kit ?worktable)))
 ; source: <https://w3id.org/kitkb/kitting-domain#look-at-part-on-worktable>
 (:action look-at-part-on-worktable
  :parameters ( ?robot - robot ?part - part ?worktable - worktable)
  :precondition (and (part-location-worktable ?part ?worktable))
  :effect (and (part-quality-ok ?part)))
 ; source: <https://w3id.org/kitkb/kitting-domain#look-for-part>
 (:action look-for-part
  :parameters ( ?robot - robot ?part - part ?partstray - partstray)
  :precondition (and (part-location-partstray ?part ?partstray) (partstray-not-empty ?partstray) (robot-empty ?robot))
  :effect (and (part-quality-ok ?part)))
 ; source: <https://w3id.org/kitkb/kitting-domain#put-kit>
 (:action put-kit
  :parameters ( ?robot - robot ?kit - kit ?lbwk - largeboxwithkits)
  :precondition (and (kit-location-robot ?kit ?robot) (lbwk-not-full ?lbwk) (robot-holds-kit ?robot ?kit))
  :effect (and (not (kit-location-robot ?kit ?robot)) (not (robot-holds-kit ?robot ?kit)) (kit-location-lbwk ?kit ?lbwk) (robot-empty ?robot)))
 ; source: <https://w3id.org/kitkb/kitting-domain#put-kittray>
 (:action put-kittray
  :parameters ( ?robot - robot ?kittray - kittray ?worktable - worktable)
  :precondition (and (kittray-location-robot ?kittray ?robot) (robot-holds-kittray ?robot ?kittray) (worktable-empty ?worktable))
  :effect (and (not (kittray-location-robot ?kittray ?robot)) (not (robot-holds-kittray ?robot ?kittray)) (not (worktable-empty ?worktable)) (kittray-location-worktable ?kittray ?worktable) (robot-empty ?robot)))
 ; source: <https://w3id.org/kitkb/kitting-domain#put-part>
 (:action put-part
  :parameters ( ?robot - robot ?part - part ?kit - kit ?worktable - worktable ?sku - stockkeepingunit)
  :precondition (and (kit-location-worktable ?kit ?worktable) (part-location-robot ?part ?robot) (part-sku ?part ?sku) (robot-holds-part ?robot ?part) (quantity-kit-pending ?kit ?sku ?part))
  :effect (and (not (part-location-robot ?part ?robot)) (not (robot-holds-part ?robot ?part)) (not (quantity-kit-pending ?kit ?sku ?part)) (part-location-kit ?part ?kit) (robot-empty ?robot) (quantity-kit-counted ?kit ?sku ?part)))
 ; source: <https://w3id.org/kitkb/kitting-domain#reject-part-from-worktable>
 (:action reject-part-from-worktable
  :parameters ( ?robot - robot ?part - part ?worktable - worktable ?endeffector - endeffector ?rejectbin - rejectbin)
  :precondition (and (endeffector-location-robot ?endeffector ?robot) (endeffector-type-part ?endeffector ?part) (part-location-worktable ?part ?worktable) (robot-empty ?robot) (robot-with-endeffector ?robot ?endeffector))
  :effect (and (not (part-location-worktable ?part ?worktable)) (part-location-rejectbin ?part ?rejectbin)))
 ; source: <https://w3id.org/kitkb/kitting-domain#remove-endeffector>
 (:action remove-endeffector
  :parameters ( ?robot - robot ?endeffector - endeffector ?endeffectorholder - endeffectorholder ?changingstation - endeffectorchangingstation)
  :precondition (and (endeffector-location-robot ?endeffector ?robot) (endeffectorholder-empty ?endeffectorholder) (endeffectorholder-location-changingstation ?endeffectorholder ?changingstation) (robot-empty ?robot) (robot-with-endeffector ?robot ?endeffector))
  :effect (and (not (endeffector-location-robot ?endeffector ?robot)) (not (endeffectorholder-empty ?endeffectorholder)) (not (robot-with-endeffector ?robot ?endeffector)) (endeffector-location-endeffectorholder ?endeffector ?endeffectorholder) (robot-with-no-endeffector ?robot)))
 ; source: <https://w3id.org/kitkb/kitting-domain#take-kit>
 (:action take-kit
  :parameters ( ?robot - robot ?kit - kit ?worktable - worktable ?endeffector - endeffector)
  :precondition (and (endeffector-location-robot ?endeffector ?robot) (endeffector-type-kit ?endeffector ?kit) (kit-location-worktable ?kit ?worktable) (robot-empty ?robot) (robot-with-endeffector ?robot ?endeffector))
  :effect (and (not (kit-location-worktable ?kit ?worktable)) (not (robot-empty ?robot)) (kit-location-robot ?kit ?robot) (robot-holds-kit ?robot ?kit) (worktable-empty ?worktable)))
 ; source: <https://w3id.org/kitkb/kitting-domain#take-kittray>
 (:action take-kittray
  :parameters ( ?robot - robot ?kittray - kittray ?lbwekt - largeboxwithemptykittrays ?endeffector - endeffector)
  :precondition (and (endeffector-location-robot ?endeffector ?robot) (endeffector-type-kittray ?endeffector ?kittray) (kittray-location-lbwekt ?kittray ?lbwekt) (robot-empty ?robot) (robot-with-endeffector ?robot ?endeffector))
  :effect (and (not (kittray-location-lbwekt ?kittray ?lbwekt)) (not (robot-empty ?robot)) (kittray-location-robot ?kittray ?robot) (robot-holds-kittray ?robot ?kittray)))
 ; source: <https://w3id.org/kitkb/kitting-domain#take-part>
 (:action take-part
  :parameters ( ?robot - robot ?part - part ?partstray - partstray ?endeffector - endeffector)
  :precondition (and (endeffector-location-robot ?endeffector ?robot) (endeffector-type-part ?endeffector ?part) (part-location-partstray ?part ?partstray) (partstray-not-empty ?partstray) (robot-empty ?robot) (robot-with-endeffector ?robot ?endeffector))
  :effect (and (not (part-location-partstray ?part ?partstray)) (not (robot-empty ?robot)) (part-location-robot ?part ?robot) (robot-holds-part ?robot ?part)))
 ; source: <https://w3id.org/kitkb/kitting-domain#take-part-from-worktable>
 (:action take-part-from-worktable
  :parameters ( ?robot - robot ?part - part ?worktable - worktable ?endeffector - endeffector)
  :precondition (and (endeffector-location-robot ?endeffector ?robot) (endeffector-type-part ?endeffector ?part) (part-location-worktable ?part ?worktable) (robot-empty ?robot) (robot-with-endeffector ?robot ?endeffector))
  :effect (and (not (part-location-worktable ?part ?worktable)) (not (robot-empty ?robot)) (part-location-robot ?part ?robot) (robot-holds-part ?robot ?part)))
)
