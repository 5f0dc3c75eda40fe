; A tidy-up with derived predicates (axioms): where the robot can get to is the transitive closure
; of the open doors from where it stands (recursive rules), a room is dark where no lamp in it is
; on (a negated basic predicate), a room is cut off where it cannot be reached (the negation of a
; derived predicate: a second stratum), and the goal is one derived atom over all the items.
(define (domain derived-tidy)
  (:requirements :typing :negative-preconditions :existential-preconditions
                 :universal-preconditions :derived-predicates :action-costs :probabilities :strata)
  (:types room door item lamp)
  (:predicates
    (robot-in ?r - room) (door-between ?d - door ?a ?b - room) (open ?d - door)
    (item-in ?o - item ?r - room) (holding ?o - item) (hand-empty) (belongs ?o - item ?r - room)
    (lamp-in ?l - lamp ?r - room) (on ?l - lamp)
    (reachable ?r - room) (dark ?r - room) (cut-off ?r - room) (tidy))
  (:functions (total-cost) - number)

  (:derived (reachable ?r - room) (robot-in ?r))
  (:derived (reachable ?r - room)
    (exists (?s - room ?d - door) (and (reachable ?s) (door-between ?d ?s ?r) (open ?d))))
  (:derived (dark ?r - room) (not (exists (?l - lamp) (and (lamp-in ?l ?r) (on ?l)))))
  (:derived (cut-off ?r - room) (not (reachable ?r)))
  (:derived (tidy) (forall (?o - item) (exists (?r - room) (and (item-in ?o ?r) (belongs ?o ?r)))))

  (:action go
    :parameters (?from ?to - room)
    :precondition (and (robot-in ?from) (reachable ?to) (not (dark ?to)))
    :effect (and (not (robot-in ?from)) (robot-in ?to) (increase (total-cost) 2)))
  (:action open-door
    :parameters (?d - door ?a ?b - room)
    :precondition (and (robot-in ?a) (door-between ?d ?a ?b) (not (open ?d)))
    :effect (and (open ?d) (increase (total-cost) 1)))
  (:action switch-on
    :parameters (?l - lamp ?r - room)
    :precondition (and (lamp-in ?l ?r) (reachable ?r) (not (on ?l)))
    :effect (and (on ?l) (increase (total-cost) 1)))
  (:action take
    :parameters (?o - item ?r - room)
    :probability 0.9
    :precondition (and (robot-in ?r) (item-in ?o ?r) (hand-empty) (not (dark ?r)))
    :effect (and (holding ?o) (not (item-in ?o ?r)) (not (hand-empty)) (increase (total-cost) 1)))
  (:action put
    :parameters (?o - item ?r - room)
    :precondition (and (robot-in ?r) (holding ?o))
    :effect (and (item-in ?o ?r) (not (holding ?o)) (hand-empty) (increase (total-cost) 1)))
  ; a throw across an open door: the second O-FSM stratum, used only where stratum 1 has no plan
  (:action throw
    :parameters (?o - item ?from ?to - room)
    :stratum 2
    :precondition (and (robot-in ?from) (holding ?o) (reachable ?to) (not (cut-off ?to)))
    :effect (and (item-in ?o ?to) (not (holding ?o)) (hand-empty) (increase (total-cost) 1))))
