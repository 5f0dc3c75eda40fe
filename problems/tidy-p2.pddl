;; tidy-p2: a deposit's standard waypoint is unreachable by path (the paper's P2 case,
;; Table I: "p_d unreachable"). container-a (kitchen) is delivered to from wp-container,
;; and no known path leads INTO wp-container (its goal pose lies in the inflated
;; costmap along the deposit table); a 0.50 m ego-pose adjustment from wp-tray reaches
;; it. Leaving wp-container by path is fine. Stratum 1 alone has no plan (o3 cannot be
;; delivered); stratum 2 (P2 = P1 + possible_ego_pose_adjustment) has.
;;
;; Expected optimal plan (seconds: c = 56.32 s of moves + 47.7 s = 104.02):
;;   move wp-entrance wp-o1 (5.89); take_object o1 wp-o1
;;   move wp-o1 wp-tray (6.80); deliver_it o1 tray1 wp-tray food
;;   move wp-tray wp-o3 (10.53); take_object o3 wp-o3
;;   move wp-o3 wp-tray (10.53)
;;   possible_ego_pose_adjustment wp-tray wp-container (3.07)        <- stratum 2
;;   deliver_it o3 container-a wp-container kitchen
;;   move wp-container wp-o2 (8.75); take_object o2 wp-o2
;;   move wp-o2 wp-tray (10.75); deliver_it o2 tray1 wp-tray food
;; p = 0.95^3 * 0.98^3 = 0.8070, c + 1000(1 - p) = 297.07.
;; Note: (travel-time wp-tray wp-container) is the adjustment's time; no path joins them.

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
    (pose-adjustment wp-tray wp-container) (= (travel-time wp-tray wp-container) 3.07)
    ;; known collision-free paths h(x,y) and the robot's time along them: the length k(x,y)
    ;; at 0.22 m/s plus a 0.8 s stop
    (path wp-entrance wp-tray) (= (travel-time wp-entrance wp-tray) 11.71)
    (path wp-entrance wp-o1) (= (travel-time wp-entrance wp-o1) 5.89)
    (path wp-entrance wp-o2) (= (travel-time wp-entrance wp-o2) 14.62)
    (path wp-entrance wp-o3) (= (travel-time wp-entrance wp-o3) 10.30)
    (path wp-tray wp-entrance) (= (travel-time wp-tray wp-entrance) 11.71)
    (path wp-tray wp-o1) (= (travel-time wp-tray wp-o1) 6.80)
    (path wp-tray wp-o2) (= (travel-time wp-tray wp-o2) 10.75)
    (path wp-tray wp-o3) (= (travel-time wp-tray wp-o3) 10.53)
    (path wp-container wp-entrance) (= (travel-time wp-container wp-entrance) 12.57)
    (path wp-container wp-tray) (= (travel-time wp-container wp-tray) 3.07)
    (path wp-container wp-o1) (= (travel-time wp-container wp-o1) 7.53)
    (path wp-container wp-o2) (= (travel-time wp-container wp-o2) 8.75)
    (path wp-container wp-o3) (= (travel-time wp-container wp-o3) 9.35)
    (path wp-o1 wp-entrance) (= (travel-time wp-o1 wp-entrance) 5.89)
    (path wp-o1 wp-tray) (= (travel-time wp-o1 wp-tray) 6.80)
    (path wp-o1 wp-o2) (= (travel-time wp-o1 wp-o2) 10.98)
    (path wp-o1 wp-o3) (= (travel-time wp-o1 wp-o3) 7.85)
    (path wp-o2 wp-entrance) (= (travel-time wp-o2 wp-entrance) 14.62)
    (path wp-o2 wp-tray) (= (travel-time wp-o2 wp-tray) 10.75)
    (path wp-o2 wp-o1) (= (travel-time wp-o2 wp-o1) 10.98)
    (path wp-o2 wp-o3) (= (travel-time wp-o2 wp-o3) 5.62)
    (path wp-o3 wp-entrance) (= (travel-time wp-o3 wp-entrance) 10.30)
    (path wp-o3 wp-tray) (= (travel-time wp-o3 wp-tray) 10.53)
    (path wp-o3 wp-o1) (= (travel-time wp-o3 wp-o1) 7.85)
    (path wp-o3 wp-o2) (= (travel-time wp-o3 wp-o2) 5.62))
  (:goal (and (tidied o1) (tidied o2) (tidied o3)))
  (:metric minimize (total-cost)))
