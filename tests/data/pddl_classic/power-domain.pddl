;; Shaped like IPC 2004's PSR with derived predicates: which devices are fed is a
;; transitive closure over the closed devices from the breakers (a recursive derived
;; predicate); whether a line is fed is derived from it; the goal negates one of them.
(define (domain power-supply)
  (:requirements :typing :adl :derived-predicates)
  (:types device line - object
          breaker switch - device)
  (:predicates (closed ?d - device)
               (con ?a - device ?b - device)
               (ext ?l - line ?d - device)
               (fed ?d - device)
               (line-fed ?l - line))
  (:derived (fed ?b - breaker) (closed ?b))
  (:derived (fed ?d - device)
     (and (closed ?d)
          (exists (?e - device) (and (con ?e ?d) (fed ?e)))))
  (:derived (line-fed ?l - line)
     (exists (?d - device) (and (ext ?l ?d) (fed ?d))))
  (:action close
     :parameters (?d - device)
     :precondition (not (closed ?d))
     :effect (closed ?d))
  (:action open
     :parameters (?d - device)
     :precondition (closed ?d)
     :effect (not (closed ?d))))
