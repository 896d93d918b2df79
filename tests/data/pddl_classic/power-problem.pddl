(define (problem power-supply-1)
  (:domain power-supply)
  (:objects b1 - breaker s1 s2 s3 - switch l1 l2 l3 - line)
  (:init (con b1 s1) (con s1 s2) (con s2 s3)
         (ext l1 s1) (ext l2 s2) (ext l3 s3)
         (closed s3))
  ; l3 is faulty: it must stay without power
  (:goal (and (line-fed l1) (line-fed l2) (not (line-fed l3)))))
