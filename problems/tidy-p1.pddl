;; tidy-p1: fully observable, fully reachable (the paper's FOFR, Sec. III-A): 4 items in
;; 2 categories (food -> tray1, kitchen -> container-a), every waypoint joined to every
;; other by a known path whose length is the straight line (room frame: x along the 3.5 m
;; wall, y along the 4 m one; deposits along the x = 0 wall, entrance at (3.0, 0.5)).
;; Only stratum 1 (P1 = take_object, move, deliver_it) is needed.
;;
;; Expected optimal plan (c = 14.69 m of moves + 8 manipulations = 22.69):
;;   move wp-entrance wp-o1         1.12
;;   take_object o1 wp-o1           1
;;   move wp-o1 wp-tray             1.32
;;   deliver_it o1 tray1 wp-tray food                1
;;   move wp-tray wp-o2             2.14
;;   take_object o2 wp-o2           1
;;   move wp-o2 wp-container        1.73
;;   deliver_it o2 container-a wp-container kitchen  1
;;   move wp-container wp-o4        2.42
;;   take_object o4 wp-o4           1
;;   move wp-o4 wp-container        2.42
;;   deliver_it o4 container-a wp-container kitchen  1
;;   move wp-container wp-o3        1.35
;;   take_object o3 wp-o3           1
;;   move wp-o3 wp-tray             2.19
;;   deliver_it o3 tray1 wp-tray food                1
;; p = 0.95^4 * 0.98^4 = 0.7513 (every plan has it), c + 1000(1 - p) = 271.42.
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
    ;; known collision-free paths h(x,y) and their lengths k(x,y) in metres
    (path wp-entrance wp-tray) (= (distance wp-entrance wp-tray) 2.40)
    (path wp-entrance wp-container) (= (distance wp-entrance wp-container) 2.86)
    (path wp-entrance wp-o1) (= (distance wp-entrance wp-o1) 1.12)
    (path wp-entrance wp-o2) (= (distance wp-entrance wp-o2) 2.09)
    (path wp-entrance wp-o3) (= (distance wp-entrance wp-o3) 3.04)
    (path wp-entrance wp-o4) (= (distance wp-entrance wp-o4) 2.91)
    (path wp-tray wp-entrance) (= (distance wp-tray wp-entrance) 2.40)
    (path wp-tray wp-container) (= (distance wp-tray wp-container) 1.00)
    (path wp-tray wp-o1) (= (distance wp-tray wp-o1) 1.32)
    (path wp-tray wp-o2) (= (distance wp-tray wp-o2) 2.14)
    (path wp-tray wp-o3) (= (distance wp-tray wp-o3) 2.19)
    (path wp-tray wp-o4) (= (distance wp-tray wp-o4) 3.04)
    (path wp-container wp-entrance) (= (distance wp-container wp-entrance) 2.86)
    (path wp-container wp-tray) (= (distance wp-container wp-tray) 1.00)
    (path wp-container wp-o1) (= (distance wp-container wp-o1) 1.77)
    (path wp-container wp-o2) (= (distance wp-container wp-o2) 1.73)
    (path wp-container wp-o3) (= (distance wp-container wp-o3) 1.35)
    (path wp-container wp-o4) (= (distance wp-container wp-o4) 2.42)
    (path wp-o1 wp-entrance) (= (distance wp-o1 wp-entrance) 1.12)
    (path wp-o1 wp-tray) (= (distance wp-o1 wp-tray) 1.32)
    (path wp-o1 wp-container) (= (distance wp-o1 wp-container) 1.77)
    (path wp-o1 wp-o2) (= (distance wp-o1 wp-o2) 1.55)
    (path wp-o1 wp-o3) (= (distance wp-o1 wp-o3) 2.24)
    (path wp-o1 wp-o4) (= (distance wp-o1 wp-o4) 2.53)
    (path wp-o2 wp-entrance) (= (distance wp-o2 wp-entrance) 2.09)
    (path wp-o2 wp-tray) (= (distance wp-o2 wp-tray) 2.14)
    (path wp-o2 wp-container) (= (distance wp-o2 wp-container) 1.73)
    (path wp-o2 wp-o1) (= (distance wp-o2 wp-o1) 1.55)
    (path wp-o2 wp-o3) (= (distance wp-o2 wp-o3) 1.06)
    (path wp-o2 wp-o4) (= (distance wp-o2 wp-o4) 0.98)
    (path wp-o3 wp-entrance) (= (distance wp-o3 wp-entrance) 3.04)
    (path wp-o3 wp-tray) (= (distance wp-o3 wp-tray) 2.19)
    (path wp-o3 wp-container) (= (distance wp-o3 wp-container) 1.35)
    (path wp-o3 wp-o1) (= (distance wp-o3 wp-o1) 2.24)
    (path wp-o3 wp-o2) (= (distance wp-o3 wp-o2) 1.06)
    (path wp-o3 wp-o4) (= (distance wp-o3 wp-o4) 1.22)
    (path wp-o4 wp-entrance) (= (distance wp-o4 wp-entrance) 2.91)
    (path wp-o4 wp-tray) (= (distance wp-o4 wp-tray) 3.04)
    (path wp-o4 wp-container) (= (distance wp-o4 wp-container) 2.42)
    (path wp-o4 wp-o1) (= (distance wp-o4 wp-o1) 2.53)
    (path wp-o4 wp-o2) (= (distance wp-o4 wp-o2) 0.98)
    (path wp-o4 wp-o3) (= (distance wp-o4 wp-o3) 1.22))
  (:goal (and (tidied o1) (tidied o2) (tidied o3) (tidied o4)))
  (:metric minimize (total-cost)))
