; Conventions seen in hand-written and IPC files: mixed case, comments everywhere (also
; right after a name), no :requirements, sections in another order than the BNF, domain
; constants, CRLF line ends.
(DEFINE (DOMAIN Conventions);the domain
  (:CONSTANTS Home - Place)   ; a constant before the types
  (:TYPES Place Robot;robots
          Item)
  (:PREDICATES (At ?r - Robot ?p - Place) (Holds ?r - Robot ?i - Item)
               (Lies ?i - Item ?p - Place) (Link ?a ?b - Place))
  (:ACTION Go :PARAMETERS (?r - Robot ?from ?to - Place)
     :PRECONDITION (AND (At ?r ?from) (Link ?from ?to))
     :EFFECT (AND (NOT (At ?r ?from)) (At ?r ?to)))
  (:action Take :parameters (?r - Robot ?i - Item ?p - Place)
     :precondition (and (At ?r ?p) (Lies ?i ?p))
     :effect (and (Holds ?r ?i) (not (Lies ?i ?p))))
  (:action Leave :parameters (?r - Robot ?i - Item)
     :precondition (and (At ?r Home) (Holds ?r ?i))
     :effect (and (Lies ?i Home) (not (Holds ?r ?i)))))
