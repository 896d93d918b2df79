(define (problem Conventions-1) (:domain CONVENTIONS)
  ;; objects named like PDDL keywords, and names a reader of the BNF alone refuses
  (:objects R2D2 - robot
            and not at either object forall - place
            1st - item   ; starts with a digit
            box.7 - item)
  (:init (at r2d2 and) (link and not) (link not home) (link home at) (link at either)
         (link either object) (link object forall) (link forall home)
         (lies 1st not) (lies box.7 forall))
  (:goal (and (lies 1st home) (lies box.7 home) (at r2d2 either))))
