(define (problem gap-r1000) (:domain gap)
  (:init (start))
  (:goal (done)))
