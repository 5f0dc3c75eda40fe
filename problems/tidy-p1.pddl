;; tidy-p1: fully observable, fully reachable (the paper's FOFR, Sec. III-A): 4 items in
;; 2 categories (food -> tray1, kitchen -> container-a), every waypoint joined to every
;; other by a known path whose length is the straight line (room frame: x along the 3.5 m
;; wall, y along the 4 m one; deposits along the x = 0 wall, entrance at (3.0, 0.5)).
;; Only stratum 1 (P1 = take_object, move, deliver_it) is needed.
;;
;; Expected optimal plan (costs in seconds: c = 73.17 s of moves + 63.6 s of takes and
;; deliveries = 136.77):
;;   move wp-entrance wp-o1         5.89
;;   take_object o1 wp-o1           5.7
;;   move wp-o1 wp-tray             6.80
;;   deliver_it o1 tray1 wp-tray food                10.2
;;   move wp-tray wp-o2             10.53
;;   take_object o2 wp-o2           5.7
;;   move wp-o2 wp-container        8.66
;;   deliver_it o2 container-a wp-container kitchen  10.2
;;   move wp-container wp-o4        11.80
;;   take_object o4 wp-o4           5.7
;;   move wp-o4 wp-container        11.80
;;   deliver_it o4 container-a wp-container kitchen  10.2
;;   move wp-container wp-o3        6.94
;;   take_object o3 wp-o3           5.7
;;   move wp-o3 wp-tray             10.75
;;   deliver_it o3 tray1 wp-tray food                10.2
;; p = 0.95^4 * 0.98^4 = 0.7513 (every plan has it), c + 1000(1 - p) = 385.50.
;; Checked with Fast Downward astar(lmcut()) on a stripped copy, and `tidyplan plan
;; --planner optimal`.

(define (problem tidy-p1)
  (:domain tidy)
  (:objects
    wp-entrance wp-tray wp-container wp-o1 wp-o2 wp-o3 wp-o4 - waypoint
    o1 o2 o3 o4 - item
    tray1 container-a - deposit
    food kitchen - category)
  (:init
    (= (total-cost) 0)
    (robot-at wp-entrance) (hand-empty)
    (item-at o1 wp-o1) (item-at o2 wp-o2) (item-at o3 wp-o3) (item-at o4 wp-o4)
    (of-category o1 food) (of-category o3 food)
    (of-category o2 kitchen) (of-category o4 kitchen)
    (deposit-at tray1 wp-tray) (accepts tray1 food)
    (deposit-at container-a wp-container) (accepts container-a kitchen)
    ;; known collision-free paths h(x,y) and the robot's time along them: the length k(x,y)
    ;; at 0.22 m/s plus a 0.8 s stop
    (path wp-entrance wp-tray) (= (travel-time wp-entrance wp-tray) 11.71)
    (path wp-entrance wp-container) (= (travel-time wp-entrance wp-container) 13.80)
    (path wp-entrance wp-o1) (= (travel-time wp-entrance wp-o1) 5.89)
    (path wp-entrance wp-o2) (= (travel-time wp-entrance wp-o2) 10.30)
    (path wp-entrance wp-o3) (= (travel-time wp-entrance wp-o3) 14.62)
    (path wp-entrance wp-o4) (= (travel-time wp-entrance wp-o4) 14.03)
    (path wp-tray wp-entrance) (= (travel-time wp-tray wp-entrance) 11.71)
    (path wp-tray wp-container) (= (travel-time wp-tray wp-container) 5.35)
    (path wp-tray wp-o1) (= (travel-time wp-tray wp-o1) 6.80)
    (path wp-tray wp-o2) (= (travel-time wp-tray wp-o2) 10.53)
    (path wp-tray wp-o3) (= (travel-time wp-tray wp-o3) 10.75)
    (path wp-tray wp-o4) (= (travel-time wp-tray wp-o4) 14.62)
    (path wp-container wp-entrance) (= (travel-time wp-container wp-entrance) 13.80)
    (path wp-container wp-tray) (= (travel-time wp-container wp-tray) 5.35)
    (path wp-container wp-o1) (= (travel-time wp-container wp-o1) 8.85)
    (path wp-container wp-o2) (= (travel-time wp-container wp-o2) 8.66)
    (path wp-container wp-o3) (= (travel-time wp-container wp-o3) 6.94)
    (path wp-container wp-o4) (= (travel-time wp-container wp-o4) 11.80)
    (path wp-o1 wp-entrance) (= (travel-time wp-o1 wp-entrance) 5.89)
    (path wp-o1 wp-tray) (= (travel-time wp-o1 wp-tray) 6.80)
    (path wp-o1 wp-container) (= (travel-time wp-o1 wp-container) 8.85)
    (path wp-o1 wp-o2) (= (travel-time wp-o1 wp-o2) 7.85)
    (path wp-o1 wp-o3) (= (travel-time wp-o1 wp-o3) 10.98)
    (path wp-o1 wp-o4) (= (travel-time wp-o1 wp-o4) 12.30)
    (path wp-o2 wp-entrance) (= (travel-time wp-o2 wp-entrance) 10.30)
    (path wp-o2 wp-tray) (= (travel-time wp-o2 wp-tray) 10.53)
    (path wp-o2 wp-container) (= (travel-time wp-o2 wp-container) 8.66)
    (path wp-o2 wp-o1) (= (travel-time wp-o2 wp-o1) 7.85)
    (path wp-o2 wp-o3) (= (travel-time wp-o2 wp-o3) 5.62)
    (path wp-o2 wp-o4) (= (travel-time wp-o2 wp-o4) 5.25)
    (path wp-o3 wp-entrance) (= (travel-time wp-o3 wp-entrance) 14.62)
    (path wp-o3 wp-tray) (= (travel-time wp-o3 wp-tray) 10.75)
    (path wp-o3 wp-container) (= (travel-time wp-o3 wp-container) 6.94)
    (path wp-o3 wp-o1) (= (travel-time wp-o3 wp-o1) 10.98)
    (path wp-o3 wp-o2) (= (travel-time wp-o3 wp-o2) 5.62)
    (path wp-o3 wp-o4) (= (travel-time wp-o3 wp-o4) 6.35)
    (path wp-o4 wp-entrance) (= (travel-time wp-o4 wp-entrance) 14.03)
    (path wp-o4 wp-tray) (= (travel-time wp-o4 wp-tray) 14.62)
    (path wp-o4 wp-container) (= (travel-time wp-o4 wp-container) 11.80)
    (path wp-o4 wp-o1) (= (travel-time wp-o4 wp-o1) 12.30)
    (path wp-o4 wp-o2) (= (travel-time wp-o4 wp-o2) 5.25)
    (path wp-o4 wp-o3) (= (travel-time wp-o4 wp-o3) 6.35))
  (:goal (and (tidied o1) (tidied o2) (tidied o3) (tidied o4)))
  (:metric minimize (total-cost)))
