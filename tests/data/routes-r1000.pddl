(define (problem routes-r1000) (:domain routes)
  (:init (start))
  (:goal (done))
  (:goal-reward 1000))
