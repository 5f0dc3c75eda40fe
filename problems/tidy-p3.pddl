;; tidy-p3: an obstruction on the floor (the paper's P3 case, Table I: "p_i
;; unreachable", Algorithm 1). Item ob (category `unknown`) lies in the gap that is the
;; only way to and from wp-o1, so every path into or out of wp-o1 is `blocked` until ob
;; is taken. No deposit accepts `unknown`, so ob cannot be delivered: the robot must
;; carry it to the removal waypoint wp-removal (by the entrance; reached on the way in,
;; neither a grasp nor a delivery waypoint: Algorithm 1), drop it there, move back,
;; then tidy the rest. ob is not in the goal. Strata 1 and 2 have no plan; stratum 3
;; (P3 = P2 + drop_object, move_back) has.
;;
;; Expected optimal plan (seconds: c = 51.54 s of moves + 48.0 s = 99.54):
;;   move wp-entrance wp-ob (11.57); take_object ob wp-ob      ; frees the paths to wp-o1
;;   move wp-ob wp-removal (8.94); drop_object ob wp-removal  ; stratum 3
;;   move_back wp-removal wp-o2 (3.85)                        ; stratum 3
;;   take_object o2 wp-o2; move wp-o2 wp-container (8.98)
;;   deliver_it o2 container-a wp-container kitchen
;;   move wp-container wp-o1 (6.85); take_object o1 wp-o1
;;   move wp-o1 wp-tray (11.35); deliver_it o1 tray1 wp-tray food
;; p = 0.95^3 * 0.98^2 * 0.98 (drop) = 0.8070, c + 1000(1 - p) = 292.59.

(define (problem tidy-p3)
  (:domain tidy)
  (:objects
    wp-entrance wp-removal wp-tray wp-container wp-ob wp-o1 wp-o2 - waypoint
    o1 o2 ob - item
    tray1 container-a - deposit
    food kitchen unknown - category)
  (:init
    (= (total-cost) 0)
    (robot-at wp-entrance) (hand-empty)
    (item-at o1 wp-o1) (item-at o2 wp-o2) (item-at ob wp-ob)
    (of-category o1 food) (of-category o2 kitchen) (of-category ob unknown)
    (deposit-at tray1 wp-tray) (accepts tray1 food)
    (deposit-at container-a wp-container) (accepts container-a kitchen)
    ;; no deposit accepts `unknown` here (bin B is absent from this scenario)
    (removal-waypoint ob wp-removal)
    ;; ob lies on the floor in the gap that is the only way to and from wp-o1
    (blocks ob wp-entrance wp-o1) (blocked wp-entrance wp-o1)
    (blocks ob wp-removal wp-o1) (blocked wp-removal wp-o1)
    (blocks ob wp-tray wp-o1) (blocked wp-tray wp-o1)
    (blocks ob wp-container wp-o1) (blocked wp-container wp-o1)
    (blocks ob wp-ob wp-o1) (blocked wp-ob wp-o1)
    (blocks ob wp-o2 wp-o1) (blocked wp-o2 wp-o1)
    (blocks ob wp-o1 wp-entrance) (blocked wp-o1 wp-entrance)
    (blocks ob wp-o1 wp-removal) (blocked wp-o1 wp-removal)
    (blocks ob wp-o1 wp-tray) (blocked wp-o1 wp-tray)
    (blocks ob wp-o1 wp-container) (blocked wp-o1 wp-container)
    (blocks ob wp-o1 wp-ob) (blocked wp-o1 wp-ob)
    (blocks ob wp-o1 wp-o2) (blocked wp-o1 wp-o2)
    ;; known collision-free paths h(x,y) and the robot's time along them: the length k(x,y)
    ;; at 0.22 m/s plus a 0.8 s stop
    (path wp-entrance wp-removal) (= (travel-time wp-entrance wp-removal) 3.44)
    (path wp-entrance wp-tray) (= (travel-time wp-entrance wp-tray) 11.71)
    (path wp-entrance wp-container) (= (travel-time wp-entrance wp-container) 13.80)
    (path wp-entrance wp-ob) (= (travel-time wp-entrance wp-ob) 11.57)
    (path wp-entrance wp-o1) (= (travel-time wp-entrance wp-o1) 17.21)
    (path wp-entrance wp-o2) (= (travel-time wp-entrance wp-o2) 6.48)
    (path wp-removal wp-entrance) (= (travel-time wp-removal wp-entrance) 3.44)
    (path wp-removal wp-tray) (= (travel-time wp-removal wp-tray) 9.94)
    (path wp-removal wp-container) (= (travel-time wp-removal wp-container) 11.39)
    (path wp-removal wp-ob) (= (travel-time wp-removal wp-ob) 8.94)
    (path wp-removal wp-o1) (= (travel-time wp-removal wp-o1) 14.53)
    (path wp-removal wp-o2) (= (travel-time wp-removal wp-o2) 3.85)
    (path wp-tray wp-entrance) (= (travel-time wp-tray wp-entrance) 11.71)
    (path wp-tray wp-removal) (= (travel-time wp-tray wp-removal) 9.94)
    (path wp-tray wp-container) (= (travel-time wp-tray wp-container) 5.35)
    (path wp-tray wp-ob) (= (travel-time wp-tray wp-ob) 9.16)
    (path wp-tray wp-o1) (= (travel-time wp-tray wp-o1) 11.35)
    (path wp-tray wp-o2) (= (travel-time wp-tray wp-o2) 8.75)
    (path wp-container wp-entrance) (= (travel-time wp-container wp-entrance) 13.80)
    (path wp-container wp-removal) (= (travel-time wp-container wp-removal) 11.39)
    (path wp-container wp-tray) (= (travel-time wp-container wp-tray) 5.35)
    (path wp-container wp-ob) (= (travel-time wp-container wp-ob) 6.53)
    (path wp-container wp-o1) (= (travel-time wp-container wp-o1) 6.85)
    (path wp-container wp-o2) (= (travel-time wp-container wp-o2) 8.98)
    (path wp-ob wp-entrance) (= (travel-time wp-ob wp-entrance) 11.57)
    (path wp-ob wp-removal) (= (travel-time wp-ob wp-removal) 8.94)
    (path wp-ob wp-tray) (= (travel-time wp-ob wp-tray) 9.16)
    (path wp-ob wp-container) (= (travel-time wp-ob wp-container) 6.53)
    (path wp-ob wp-o1) (= (travel-time wp-ob wp-o1) 6.57)
    (path wp-ob wp-o2) (= (travel-time wp-ob wp-o2) 5.89)
    (path wp-o1 wp-entrance) (= (travel-time wp-o1 wp-entrance) 17.21)
    (path wp-o1 wp-removal) (= (travel-time wp-o1 wp-removal) 14.53)
    (path wp-o1 wp-tray) (= (travel-time wp-o1 wp-tray) 11.35)
    (path wp-o1 wp-container) (= (travel-time wp-o1 wp-container) 6.85)
    (path wp-o1 wp-ob) (= (travel-time wp-o1 wp-ob) 6.57)
    (path wp-o1 wp-o2) (= (travel-time wp-o1 wp-o2) 11.53)
    (path wp-o2 wp-entrance) (= (travel-time wp-o2 wp-entrance) 6.48)
    (path wp-o2 wp-removal) (= (travel-time wp-o2 wp-removal) 3.85)
    (path wp-o2 wp-tray) (= (travel-time wp-o2 wp-tray) 8.75)
    (path wp-o2 wp-container) (= (travel-time wp-o2 wp-container) 8.98)
    (path wp-o2 wp-ob) (= (travel-time wp-o2 wp-ob) 5.89)
    (path wp-o2 wp-o1) (= (travel-time wp-o2 wp-o1) 11.53))
  (:goal (and (tidied o1) (tidied o2)))
  (:metric minimize (total-cost)))
