(define (problem routes-r1) (:domain routes)
  (:init (start))
  (:goal (done))
  (:goal-reward 1))
