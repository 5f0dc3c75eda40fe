; a small domain for bad-input tests
(define (domain d)
  (:requirements :typing :action-costs :probabilities :assumptions :strata)
  (:types block)
  (:predicates (clear ?x - block) (on ?x ?y - block) (held ?x - block))
  (:functions (total-cost) - number)
  (:action pick
    :parameters (?x - block)
    :precondition (clear ?x)
    :effect (and (held ?x) (not (clear ?x)) (increase (total-cost) 1))))
