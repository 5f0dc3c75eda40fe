;; tidy-p2: a deposit's standard waypoint is unreachable by path (the paper's P2 case,
;; Table I: "p_d unreachable"). container-a (kitchen) is delivered to from wp-container,
;; and no known path leads INTO wp-container (its goal pose lies in the inflated
;; costmap along the deposit table); a 0.50 m ego-pose adjustment from wp-tray reaches
;; it. Leaving wp-container by path is fine. Stratum 1 alone has no plan (o3 cannot be
;; delivered); stratum 2 (P2 = P1 + possible_ego_pose_adjustment) has.
;;
;; Expected optimal plan (c = 11.16 m + 6 = 17.16):
;;   move wp-entrance wp-o1 (1.12); take_object o1 wp-o1
;;   move wp-o1 wp-tray (1.32); deliver_it o1 tray1 wp-tray food
;;   move wp-tray wp-o3 (2.14); take_object o3 wp-o3
;;   move wp-o3 wp-tray (2.14)
;;   possible_ego_pose_adjustment wp-tray wp-container (0.50)        <- stratum 2
;;   deliver_it o3 container-a wp-container kitchen
;;   move wp-container wp-o2 (1.75); take_object o2 wp-o2
;;   move wp-o2 wp-tray (2.19); deliver_it o2 tray1 wp-tray food
;; p = 0.95^3 * 0.98^3 = 0.8070, c + 1000(1 - p) = 210.21.
;; Note: (distance wp-tray wp-container) is the adjustment's length; no path joins them.

(define (problem tidy-p2)
  (:domain tidy)
  (:objects
    wp-entrance wp-tray wp-container wp-o1 wp-o2 wp-o3 - waypoint
    o1 o2 o3 - item
    tray1 container-a - deposit
    food kitchen - category)
  (:init
    (= (total-cost) 0)
    (robot-at wp-entrance) (hand-empty)
    (item-at o1 wp-o1) (item-at o2 wp-o2) (item-at o3 wp-o3)
    (of-category o1 food) (of-category o2 food) (of-category o3 kitchen)
    (deposit-at tray1 wp-tray) (accepts tray1 food)
    (deposit-at container-a wp-container) (accepts container-a kitchen)
    ;; no path leads INTO wp-container; an ego-pose adjustment from the tray's
    ;; waypoint beside it does (0.50 m sideways along the deposit table)
    (pose-adjustment wp-tray wp-container) (= (distance wp-tray wp-container) 0.50)
    ;; known collision-free paths h(x,y) and their lengths k(x,y) in metres
    (path wp-entrance wp-tray) (= (distance wp-entrance wp-tray) 2.40)
    (path wp-entrance wp-o1) (= (distance wp-entrance wp-o1) 1.12)
    (path wp-entrance wp-o2) (= (distance wp-entrance wp-o2) 3.04)
    (path wp-entrance wp-o3) (= (distance wp-entrance wp-o3) 2.09)
    (path wp-tray wp-entrance) (= (distance wp-tray wp-entrance) 2.40)
    (path wp-tray wp-o1) (= (distance wp-tray wp-o1) 1.32)
    (path wp-tray wp-o2) (= (distance wp-tray wp-o2) 2.19)
    (path wp-tray wp-o3) (= (distance wp-tray wp-o3) 2.14)
    (path wp-container wp-entrance) (= (distance wp-container wp-entrance) 2.59)
    (path wp-container wp-tray) (= (distance wp-container wp-tray) 0.50)
    (path wp-container wp-o1) (= (distance wp-container wp-o1) 1.48)
    (path wp-container wp-o2) (= (distance wp-container wp-o2) 1.75)
    (path wp-container wp-o3) (= (distance wp-container wp-o3) 1.88)
    (path wp-o1 wp-entrance) (= (distance wp-o1 wp-entrance) 1.12)
    (path wp-o1 wp-tray) (= (distance wp-o1 wp-tray) 1.32)
    (path wp-o1 wp-o2) (= (distance wp-o1 wp-o2) 2.24)
    (path wp-o1 wp-o3) (= (distance wp-o1 wp-o3) 1.55)
    (path wp-o2 wp-entrance) (= (distance wp-o2 wp-entrance) 3.04)
    (path wp-o2 wp-tray) (= (distance wp-o2 wp-tray) 2.19)
    (path wp-o2 wp-o1) (= (distance wp-o2 wp-o1) 2.24)
    (path wp-o2 wp-o3) (= (distance wp-o2 wp-o3) 1.06)
    (path wp-o3 wp-entrance) (= (distance wp-o3 wp-entrance) 2.09)
    (path wp-o3 wp-tray) (= (distance wp-o3 wp-tray) 2.14)
    (path wp-o3 wp-o1) (= (distance wp-o3 wp-o1) 1.55)
    (path wp-o3 wp-o2) (= (distance wp-o3 wp-o2) 1.06))
  (:goal (and (tidied o1) (tidied o2) (tidied o3)))
  (:metric minimize (total-cost)))
