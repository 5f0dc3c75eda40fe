;; tidy.pddl: the O-FSM tidy-up domain (Yan et al., ARSO 2021) in the tidyplan dialect.
;;
;; Mapping to the paper (Yan et al., O-FSM, Sec. IV-B, Table I):
;;   stratum 1 = P1 = {take_object, move, deliver_it, open_drawer}
;;               (Eq. 2-3: grasp an object and bring it to a deposit of its category,
;;               both reachable along known collision-free paths h(x,y); a deposit that is
;;               a closed drawer, as the WRS rules have the tools' one, is opened first).
;;   stratum 2 = P2 = P1 + {possible_ego_pose_adjustment}
;;               (Eq. 4 and "additional motions are potentially required to obtain a
;;               feasible and collision-free pose": the robot reaches a pose that no
;;               planned path leads to by adjusting its pose from a neighbouring one).
;;   stratum 3 = P3 = P2 + {drop_object, move_back}
;;               (Algorithm 1: take the obstructing object to the removal waypoint,
;;               drop it there, move back, then carry on with P1).
;; P1 is a subset of P2, which is a subset of P3. Strata rank plans lexicographically
;; (Occam's razor, Eq. 1): a plan using stratum K+1 is chosen only when none within
;; strata 1..K exists. Within a stratum the planner minimises c(pi) + R(1 - p(pi)).
;;
;; Costs are the robot's expected time in seconds, so the cheapest plan is the fastest: a
;; move costs (travel-time ?from ?to), which the problem gives (tidyplan writes the path
;; length k(x,y) at the robot's speed, 0.22 m/s for the HSR, plus 0.8 s for the stop);
;; possible_ego_pose_adjustment costs it too (a problem should not give a pair both a path
;; and a pose adjustment of different times). A take costs 5.7 s, a delivery 10.2 s and
;; opening a drawer 13.5 s: each action's mean in the pybullet HSR over 18 WRS Task 1 rooms,
;; failures and retries included (docs/results.md, "Plans in seconds", bench/clock.py); a drop
;; 10.5 s, the symbolic world's figure (too few drops in those rooms to measure).
;; Probabilities are the success rates of the manipulation actions; moves are taken
;; as certain.
;;
;; Static facts a problem provides: path, travel-time, blocks, blocks-pull, pose-adjustment,
;; removal-waypoint, deposit-at, of-category, accepts, unexplored, p-item-near, and
;; (shortest-paths) when no route via other waypoints is shorter than an open direct path
;; (nor joins two waypoints without one): moves then only go where the robot takes,
;; delivers, drops or adjusts. Leave it out where the path graph is sparse.
;; Dynamic: robot-at, hand-empty, holding, item-at, blocked, tidied, must-move-back,
;; located, closed, pull-blocked.
;; Execution: each action names the behaviour units that run it (:units, docs/dialect.md);
;; `tidyplan check` lists the units the worlds offer.
;; open_drawer is in stratum 1, not 2 or 3: opening a closed drawer is part of delivering
;; into it (the WRS rulebook's deposit is closed at the start, as a tray is empty), not an extra
;; motion around an obstacle. In a higher stratum a room whose tools go into a drawer would
;; need that stratum for every tool, and Table II would count a P1 task as P2 or P3; Occam's
;; razor ranks plans by the operators the task itself needs, and this one it always needs.
;; (removal-waypoint ?o ?w): Algorithm 1 run from where ?o is taken (its grasp waypoint):
;; the nearest waypoint already reached that is neither for grasping nor for delivery.
;; Partial observability: items seen so far are (located ...); items not yet seen are
;; virtual objects of the problem, of a known category (the room holds 3 of each), and
;; get a place only through assume-item-near.
;; An item's floor position obstructs the paths it `blocks` while it lies there: the
;; problem lists those paths as `blocked` in :init, and taking the item clears them.
;; Dropping an item back at the removal waypoint is chosen so as not to block anything.

(define (domain tidy)
  (:requirements :typing :equality :negative-preconditions :conditional-effects
                 :action-costs :probabilities :strata :assumptions)

  (:types waypoint item deposit category)

  (:predicates
    (robot-at ?w - waypoint)
    (hand-empty)
    (holding ?o - item)
    (item-at ?o - item ?w - waypoint)            ; ?o can be grasped from ?w
    (deposit-at ?d - deposit ?w - waypoint)      ; ?d can be delivered to from ?w
    (of-category ?o - item ?c - category)
    (accepts ?d - deposit ?c - category)
    (tidied ?o - item)
    (path ?from ?to - waypoint)                  ; h(x,y): a collision-free path is known
    (blocked ?from ?to - waypoint)               ; a floor item obstructs that path now
    (blocks ?o - item ?from ?to - waypoint)      ; static: ?o is that obstruction
    (pose-adjustment ?from ?to - waypoint)       ; an ego-pose adjustment reaches ?to
    (removal-waypoint ?o - item ?w - waypoint)   ; Algorithm 1's choice, from where ?o is taken
    (must-move-back)                             ; set by drop_object until move_back
    (located ?o - item)                          ; where ?o lies is known or assumed
    (closed ?d - deposit)                        ; a drawer not open: nothing goes in
    (pull-blocked ?d - deposit)                  ; a floor item lies where the base backs off to pull ?d open
    (blocks-pull ?o - item ?d - deposit)         ; static: ?o is that item
    (unexplored ?w - waypoint)                   ; nobody has looked around from ?w yet
    (shortest-paths))                            ; static: no detour beats a direct open path

  (:functions
    (total-cost) - number
    (travel-time ?from ?to - waypoint) - number  ; seconds along the path k(x,y)
    (p-item-near ?w - waypoint) - number)        ; P(an unseen item is found from ?w)

  ;; ------------------------------------------------------------- assumption
  ;; An item not yet seen (a virtual object of the problem) is assumed to be found and
  ;; grasped from a waypoint nobody has looked around from, with the probability the
  ;; problem gives (Goebelbecker's Definition 1: X = where ?o is, "not yet known" is
  ;; (not (located ?o))). Never executed: the monitor checks it against what is seen.
  (:assumption assume-item-near
    :parameters (?o - item ?w - waypoint)
    :probability (p-item-near ?w)
    :precondition (and (not (located ?o)) (unexplored ?w))
    :effect (and (located ?o) (item-at ?o ?w)))

  ;; ------------------------------------------------------------- stratum 1 (P1)
  (:action move
    :parameters (?from ?to - waypoint)
    :stratum 1
    :units ((navigate ?to))
    :precondition (and (robot-at ?from)
                       (path ?from ?to)
                       (not (blocked ?from ?to))
                       (not (must-move-back))
                       (not (= ?from ?to))
                       ;; Where the problem says its travel times are shortest, a stop
                       ;; at an idle waypoint never pays: the robot moves only to where it
                       ;; has something to do. That cuts the states a cost-optimal search
                       ;; visits on 12-object problems from 573k to 98k (docs/planner.md).
                       (or (not (shortest-paths))
                           (and (hand-empty) (exists (?o - item) (item-at ?o ?to)))
                           (exists (?o - item ?c - category ?d - deposit)
                             (and (holding ?o) (of-category ?o ?c) (accepts ?d ?c)
                                  (deposit-at ?d ?to)))
                           (exists (?o - item) (and (holding ?o) (removal-waypoint ?o ?to)))
                           (and (hand-empty) (exists (?d - deposit) (and (closed ?d) (deposit-at ?d ?to))))
                           (exists (?x - waypoint) (pose-adjustment ?to ?x))))
    :effect (and (robot-at ?to)
                 (not (robot-at ?from))
                 (increase (total-cost) (travel-time ?from ?to))))

  (:action take_object
    :parameters (?o - item ?w - waypoint)
    :stratum 1
    :probability 0.95
    :units ((adjust_base ?o) (grasp ?o))
    :precondition (and (robot-at ?w) (item-at ?o ?w) (hand-empty))
    :effect (and (holding ?o)
                 (not (item-at ?o ?w))
                 (not (hand-empty))
                 ;; picking up a floor obstruction frees the paths it blocked
                 (forall (?a ?b - waypoint)
                   (when (blocks ?o ?a ?b) (not (blocked ?a ?b))))
                 ;; and the way the base backs off to pull a drawer open
                 (forall (?d - deposit)
                   (when (blocks-pull ?o ?d) (not (pull-blocked ?d))))
                 (increase (total-cost) 5.7)))

  (:action deliver_it
    :parameters (?o - item ?d - deposit ?w - waypoint ?c - category)
    :stratum 1
    :probability 0.98
    :units ((approach_deposit ?w) (place ?o ?d ?w))
    :precondition (and (robot-at ?w)
                       (deposit-at ?d ?w)
                       (holding ?o)
                       (of-category ?o ?c)
                       (accepts ?d ?c)
                       (not (closed ?d)))
    :effect (and (tidied ?o)
                 (hand-empty)
                 (not (holding ?o))
                 (increase (total-cost) 10.2)))

  ;; A drawer is pulled open by its handle from where items are put into it, the hand free: the
;; base backs off along the slide as the drawer comes out, so a floor item in that way must be
;; taken first (pull-blocked, as a blocked path is for a move).
  (:action open_drawer
    :parameters (?d - deposit ?w - waypoint)
    :stratum 1
    :probability 0.95
    :units ((approach_handle ?w) (pull_handle ?d))
    :precondition (and (robot-at ?w) (deposit-at ?d ?w) (closed ?d) (hand-empty)
                       (not (pull-blocked ?d)))
    :effect (and (not (closed ?d))
                 (increase (total-cost) 13.5)))

  ;; ------------------------------------------------------------- stratum 2 (P2)
  (:action possible_ego_pose_adjustment
    :parameters (?from ?to - waypoint)
    :stratum 2
    :units ((adjust_pose ?to))
    :precondition (and (robot-at ?from)
                       (pose-adjustment ?from ?to)
                       (not (must-move-back)))
    :effect (and (robot-at ?to)
                 (not (robot-at ?from))
                 (increase (total-cost) (travel-time ?from ?to))))

  ;; ------------------------------------------------------------- stratum 3 (P3)
  (:action drop_object
    :parameters (?o - item ?w - waypoint)
    :stratum 3
    :probability 0.98
    :units ((put_down ?o))
    :precondition (and (robot-at ?w) (removal-waypoint ?o ?w) (holding ?o))
    :effect (and (item-at ?o ?w)
                 (hand-empty)
                 (not (holding ?o))
                 (must-move-back)
                 (increase (total-cost) 10.5)))

  (:action move_back
    :parameters (?from ?to - waypoint)
    :stratum 3
    :units ((navigate ?to))
    :precondition (and (robot-at ?from)
                       (must-move-back)
                       (path ?from ?to)
                       (not (blocked ?from ?to))
                       (not (= ?from ?to)))
    :effect (and (robot-at ?to)
                 (not (robot-at ?from))
                 (not (must-move-back))
                 (increase (total-cost) (travel-time ?from ?to)))))
