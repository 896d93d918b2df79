;; Shaped like IPC 1998's assembly and mystery: (either ...) types on predicates,
;; action parameters and quantified variables.
(define (domain either-assembly)
  (:requirements :typing :adl)
  (:types assembly resource tool - object
          gear shaft - assembly)
  (:predicates (available ?x - (either assembly resource))
               (committed ?r - (either resource tool) ?a - assembly)
               (fitted ?a - assembly ?w - assembly)
               (clean ?x - (either gear tool)))
  (:action commit
     :parameters (?r - (either resource tool) ?a - assembly)
     :precondition (available ?a)
     :effect (committed ?r ?a))
  (:action fit
     :parameters (?part - (either gear shaft) ?whole - assembly)
     :precondition (and (available ?part)
                        (forall (?r - (either resource tool)) (committed ?r ?whole))
                        (not (= ?part ?whole)))
     :effect (and (fitted ?part ?whole) (not (available ?part))))
  (:action polish-all
     :parameters ()
     :precondition (exists (?g - (either gear tool)) (not (clean ?g)))
     :effect (forall (?g - (either gear tool)) (clean ?g))))
