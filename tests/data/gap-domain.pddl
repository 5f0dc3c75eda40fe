; Where the −ln p surrogate and the exact criterion disagree (R = 1000):
; long-shot: cost 0, p 0.05 -> criterion 950, surrogate 2996
; safer:     cost 60, p 0.10 -> criterion 960, surrogate 2363
(define (domain gap)
  (:requirements :strips :action-costs :probabilities)
  (:predicates (start) (done))
  (:functions (total-cost) - number)
  (:action long-shot :probability 0.05
    :precondition (start) :effect (done))
  (:action safer :probability 0.1
    :precondition (start) :effect (and (done) (increase (total-cost) 60))))
