(define (problem blocks-axioms-4)
  (:domain blocks-axioms)
  (:objects a b c d - block)
  (:init (on c a) (ontable a) (ontable b) (on d b))
  ; the goal uses a derived predicate, negated
  (:goal (and (on a b) (on b c) (not (clear c)) (handempty))))
