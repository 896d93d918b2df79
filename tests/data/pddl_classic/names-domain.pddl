;; One name for a type and an object, a constant named like its type, objects named
;; like a predicate and an action: PDDL keeps a name space per kind, unified-planning one.
(define (domain names)
  (:requirements :strips :typing)
  (:types truck depot place - object)
  (:constants depot - depot)
  (:predicates (at ?t - truck ?p - (either place depot)) (loaded ?t - truck) (ready))
  (:action load
     :parameters (?t - truck)
     :precondition (at ?t depot)
     :effect (loaded ?t))
  (:action drive
     :parameters (?t - truck ?from ?to - (either place depot))
     :precondition (at ?t ?from)
     :effect (and (not (at ?t ?from)) (at ?t ?to))))
