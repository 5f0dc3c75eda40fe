;; tidy-rooms.pddl: a second tidy-up domain in the tidyplan dialect, written from scratch.
;;
;; Why it exists: tidy.pddl's encoding (and the planner's default, docs/planner.md) was measured
;; and tuned on tidy.pddl's own problems. This domain states the same task in other words so
;; that a bench (bench/quality_other.py) can measure whether plan quality carries over to an
;; encoding nobody tuned on. It is not tuned: no shortest-paths switch, no pruning of moves, no
;; categories; nothing in it was changed after seeing how the planner does on it.
;;
;; The task (tidy.pddl's stratum 1 without drawers): a robot drives between places, any place
;; to any connected place, at the cost of the path length; it picks one item at a time, and
;; stores it into a bin the item belongs in (item to bin directly: a problem lists every bin
;; each item may go into). Goal: (stored ?i) for each item.
;;
;; Costs: drive = (travel-cost ?from ?to), metres; pick and store 1 each (tidy.pddl's take_object
;; and deliver_it). Probabilities: pick 0.95, store 0.98, as tidy.pddl's take_object and
;; deliver_it; driving is certain. Every action is stratum 1 (P1).
;;
;; Execution: :units binds each action to the behaviour units tidy.pddl binds its counterpart to
;; (move -> navigate, take_object -> adjust_base + grasp, deliver_it -> approach_deposit + place).
;; Since this domain has :units, `tidyplan check` also holds it to the words the worlds' problems
;; are written in (tidyplan/problem.py, VOCABULARY): the types waypoint, item, deposit and
;; category must be declared, and the predicate tidied. They are declared for that reason only:
;; places are waypoints and bins deposits (so the units take them), while category and tidied
;; are used by nothing here. The worlds' problems (objects typed waypoint, goal tidied) do not fit
;; this domain: it is for planning benches, not for `tidyplan run`.

(define (domain tidy-rooms)
  (:requirements :typing :action-costs :probabilities :strata)

  (:types
    waypoint item deposit category - object
    place - waypoint                           ; where the robot can stand
    bin - deposit)                             ; where items are stored

  (:predicates
    (at-robot ?p - place)
    (free-hand)
    (carrying ?i - item)
    (on ?i - item ?p - place)                  ; ?i lies where it can be picked from ?p
    (bin-at ?bin - bin ?p - place)             ; ?bin is filled from ?p
    (belongs ?i - item ?bin - bin)             ; ?i may be stored in ?bin
    (connected ?a ?b - place)                  ; the robot can drive from ?a to ?b
    (stored ?i - item)
    (tidied ?i - item))                        ; unused: required by `tidyplan check` (above)

  (:functions
    (total-cost) - number
    (travel-cost ?a ?b - place) - number)      ; path length from ?a to ?b, metres

  (:action drive
    :parameters (?from ?to - place)
    :stratum 1
    :units ((navigate ?to))
    :precondition (and (at-robot ?from) (connected ?from ?to))
    :effect (and (not (at-robot ?from))
                 (at-robot ?to)
                 (increase (total-cost) (travel-cost ?from ?to))))

  (:action pick
    :parameters (?p - place ?i - item)
    :stratum 1
    :probability 0.95
    :units ((adjust_base ?i) (grasp ?i))
    :precondition (and (at-robot ?p) (on ?i ?p) (free-hand))
    :effect (and (not (on ?i ?p))
                 (not (free-hand))
                 (carrying ?i)
                 (increase (total-cost) 1)))

  (:action store
    :parameters (?i - item ?bin - bin ?p - place)
    :stratum 1
    :probability 0.98
    :units ((approach_deposit ?p) (place ?i ?bin ?p))
    :precondition (and (at-robot ?p) (carrying ?i) (belongs ?i ?bin) (bin-at ?bin ?p))
    :effect (and (not (carrying ?i))
                 (free-hand)
                 (stored ?i)
                 (increase (total-cost) 1))))
