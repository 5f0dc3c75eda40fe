;; tidy-strata-cheap: strata rank plans lexicographically, before cost. container-a's
;; waypoint is 0.50 m from wp-tray by an ego-pose adjustment (stratum 2), while the
;; known paths to it go round the furniture (+6 m, 27 s). The best stratum-2 plan is much
;; cheaper, yet a stratum-1 plan exists, so the stratum-1 plan must be chosen
;; (Occam's razor, O-FSM Eq. 1 / docs/dialect.md, strata).
;;
;; Expected plan, stratum 1 (seconds: c = 59.84 s + 31.8 s = 91.64; c + 1000(1 - p) = 224.88):
;;   move wp-entrance wp-o1 (5.89); take_object o1 wp-o1
;;   move wp-o1 wp-tray (6.80); deliver_it o1 tray1 wp-tray food
;;   move wp-tray wp-o2 (10.53); take_object o2 wp-o2
;;   move wp-o2 wp-container (36.62); deliver_it o2 container-a wp-container kitchen
;; NOT this cheaper stratum-2 plan (c = 36.82 s + 31.8 s = 68.62; 201.86):
;;   ... move wp-tray wp-o2 (10.53); take_object o2 wp-o2; move wp-o2 wp-tray (10.53)
;;   possible_ego_pose_adjustment wp-tray wp-container (3.07); deliver_it o2 ...
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
    (pose-adjustment wp-tray wp-container) (= (travel-time wp-tray wp-container) 3.07)
    (pose-adjustment wp-container wp-tray) (= (travel-time wp-container wp-tray) 3.07)
    ;; known collision-free paths h(x,y) and the robot's time along them: the length k(x,y)
    ;; at 0.22 m/s plus a 0.8 s stop
    (path wp-entrance wp-tray) (= (travel-time wp-entrance wp-tray) 11.71)
    (path wp-entrance wp-container) (= (travel-time wp-entrance wp-container) 39.85)
    (path wp-entrance wp-o1) (= (travel-time wp-entrance wp-o1) 5.89)
    (path wp-entrance wp-o2) (= (travel-time wp-entrance wp-o2) 10.30)
    (path wp-tray wp-entrance) (= (travel-time wp-tray wp-entrance) 11.71)
    (path wp-tray wp-o1) (= (travel-time wp-tray wp-o1) 6.80)
    (path wp-tray wp-o2) (= (travel-time wp-tray wp-o2) 10.53)
    (path wp-container wp-entrance) (= (travel-time wp-container wp-entrance) 39.85)
    (path wp-container wp-o1) (= (travel-time wp-container wp-o1) 34.80)
    (path wp-container wp-o2) (= (travel-time wp-container wp-o2) 36.62)
    (path wp-o1 wp-entrance) (= (travel-time wp-o1 wp-entrance) 5.89)
    (path wp-o1 wp-tray) (= (travel-time wp-o1 wp-tray) 6.80)
    (path wp-o1 wp-container) (= (travel-time wp-o1 wp-container) 34.80)
    (path wp-o1 wp-o2) (= (travel-time wp-o1 wp-o2) 7.85)
    (path wp-o2 wp-entrance) (= (travel-time wp-o2 wp-entrance) 10.30)
    (path wp-o2 wp-tray) (= (travel-time wp-o2 wp-tray) 10.53)
    (path wp-o2 wp-container) (= (travel-time wp-o2 wp-container) 36.62)
    (path wp-o2 wp-o1) (= (travel-time wp-o2 wp-o1) 7.85))
  (:goal (and (tidied o1) (tidied o2)))
  (:metric minimize (total-cost)))
