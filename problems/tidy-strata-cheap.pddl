;; tidy-strata-cheap: strata rank plans lexicographically, before cost. container-a's
;; waypoint is 0.50 m from wp-tray by an ego-pose adjustment (stratum 2), while the
;; known paths to it go round the furniture (+6 m). The best stratum-2 plan is much
;; cheaper, yet a stratum-1 plan exists, so the stratum-1 plan must be chosen
;; (Occam's razor, O-FSM Eq. 1 / docs/dialect.md, strata).
;;
;; Expected plan, stratum 1 (c = 12.46 m + 4 = 16.46; c + 1000(1 - p) = 149.70):
;;   move wp-entrance wp-o1 (1.12); take_object o1 wp-o1
;;   move wp-o1 wp-tray (1.32); deliver_it o1 tray1 wp-tray food
;;   move wp-tray wp-o2 (2.14); take_object o2 wp-o2
;;   move wp-o2 wp-container (7.88); deliver_it o2 container-a wp-container kitchen
;; NOT this cheaper stratum-2 plan (c = 7.22 m + 4 = 11.22; 144.46):
;;   ... move wp-tray wp-o2 (2.14); take_object o2 wp-o2; move wp-o2 wp-tray (2.14)
;;   possible_ego_pose_adjustment wp-tray wp-container (0.50); deliver_it o2 ...
;; Both have p = 0.95^2 * 0.98^2 = 0.8668, so only the stratum rule tells them apart.

(define (problem tidy-strata-cheap)
  (:domain tidy)
  (:objects
    wp-entrance wp-tray wp-container wp-o1 wp-o2 - waypoint
    o1 o2 - item
    tray1 container-a - deposit
    food kitchen - category)
  (:init
    (= (total-cost) 0)
    (robot-at wp-entrance) (hand-empty)
    (item-at o1 wp-o1) (item-at o2 wp-o2)
    (of-category o1 food) (of-category o2 kitchen)
    (deposit-at tray1 wp-tray) (accepts tray1 food)
    (deposit-at container-a wp-container) (accepts container-a kitchen)
    ;; wp-container is 0.50 m from wp-tray by an ego-pose adjustment (stratum 2);
    ;; no path joins the two. The known paths to and from wp-container go round
    ;; the drawer and the long table: 6 m longer than the straight line.
    (pose-adjustment wp-tray wp-container) (= (distance wp-tray wp-container) 0.50)
    (pose-adjustment wp-container wp-tray) (= (distance wp-container wp-tray) 0.50)
    ;; known collision-free paths h(x,y) and their lengths k(x,y) in metres
    (path wp-entrance wp-tray) (= (distance wp-entrance wp-tray) 2.40)
    (path wp-entrance wp-container) (= (distance wp-entrance wp-container) 8.59)
    (path wp-entrance wp-o1) (= (distance wp-entrance wp-o1) 1.12)
    (path wp-entrance wp-o2) (= (distance wp-entrance wp-o2) 2.09)
    (path wp-tray wp-entrance) (= (distance wp-tray wp-entrance) 2.40)
    (path wp-tray wp-o1) (= (distance wp-tray wp-o1) 1.32)
    (path wp-tray wp-o2) (= (distance wp-tray wp-o2) 2.14)
    (path wp-container wp-entrance) (= (distance wp-container wp-entrance) 8.59)
    (path wp-container wp-o1) (= (distance wp-container wp-o1) 7.48)
    (path wp-container wp-o2) (= (distance wp-container wp-o2) 7.88)
    (path wp-o1 wp-entrance) (= (distance wp-o1 wp-entrance) 1.12)
    (path wp-o1 wp-tray) (= (distance wp-o1 wp-tray) 1.32)
    (path wp-o1 wp-container) (= (distance wp-o1 wp-container) 7.48)
    (path wp-o1 wp-o2) (= (distance wp-o1 wp-o2) 1.55)
    (path wp-o2 wp-entrance) (= (distance wp-o2 wp-entrance) 2.09)
    (path wp-o2 wp-tray) (= (distance wp-o2 wp-tray) 2.14)
    (path wp-o2 wp-container) (= (distance wp-o2 wp-container) 7.88)
    (path wp-o2 wp-o1) (= (distance wp-o2 wp-o1) 1.55))
  (:goal (and (tidied o1) (tidied o2)))
  (:metric minimize (total-cost)))
