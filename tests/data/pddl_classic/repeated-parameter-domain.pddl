(define (domain repeated-parameter)
  (:requirements :strips :typing)
  (:types block)
  (:predicates (on ?x ?x - block) (clear ?x - block))
  (:action stack
     :parameters (?x ?x - block)
     :precondition (clear ?x)
     :effect (on ?x ?x)))
