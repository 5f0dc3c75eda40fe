; Two ways to the goal, after Göbelbecker et al. Sec. 2: a cheap risky one and
; a dearer safe one. Probabilities: 0.096 = 0.32 * 0.3; 0.138 = 0.46 * 0.3.
(define (domain routes)
  (:requirements :strips :action-costs :probabilities)
  (:predicates (start) (half-risky) (half-safe) (done))
  (:functions (total-cost) - number)
  (:action risky-1 :probability 0.32
    :precondition (start) :effect (and (half-risky) (increase (total-cost) 10)))
  (:action risky-2 :probability 0.3
    :precondition (half-risky) :effect (and (done) (increase (total-cost) 10)))
  (:action safe-1 :probability 0.46
    :precondition (start) :effect (and (half-safe) (increase (total-cost) 16)))
  (:action safe-2 :probability 0.3
    :precondition (half-safe) :effect (and (done) (increase (total-cost) 16))))
