; Blocksworld with derived predicates (after the IPC 2004 / Thiebaux et al. axiom
; formulation): clear and handempty are not stored, they are derived from on and holding.
(define (domain blocks-axioms)
  (:requirements :strips :typing :negative-preconditions :derived-predicates
                 :existential-preconditions)
  (:types block)
  (:predicates (on ?x - block ?y - block)
               (ontable ?x - block)
               (holding ?x - block)
               (clear ?x - block)
               (handempty))

  (:derived (clear ?x - block)
     (and (not (holding ?x))
          (not (exists (?y - block) (on ?y ?x)))))

  (:derived (handempty)
     (not (exists (?x - block) (holding ?x))))

  (:action pick-up
     :parameters (?x - block)
     :precondition (and (clear ?x) (ontable ?x) (handempty))
     :effect (and (not (ontable ?x)) (holding ?x)))

  (:action put-down
     :parameters (?x - block)
     :precondition (holding ?x)
     :effect (and (not (holding ?x)) (ontable ?x)))

  (:action stack
     :parameters (?x - block ?y - block)
     :precondition (and (holding ?x) (clear ?y))
     :effect (and (not (holding ?x)) (on ?x ?y)))

  (:action unstack
     :parameters (?x - block ?y - block)
     :precondition (and (on ?x ?y) (clear ?x) (handempty))
     :effect (and (holding ?x) (not (on ?x ?y)))))
