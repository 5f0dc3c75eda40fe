;; tidy-p3: an obstruction on the floor (the paper's P3 case, Table I: "p_i
;; unreachable", Algorithm 1). Item ob (category `unknown`) lies in the gap that is the
;; only way to and from wp-o1, so every path into or out of wp-o1 is `blocked` until ob
;; is taken. No deposit accepts `unknown`, so ob cannot be delivered: the robot must
;; carry it to the removal waypoint wp-removal (by the entrance; reached on the way in,
;; neither a grasp nor a delivery waypoint: Algorithm 1), drop it there, move back,
;; then tidy the rest. ob is not in the goal. Strata 1 and 2 have no plan; stratum 3
;; (P3 = P2 + drop_object, move_back) has.
;;
;; Expected optimal plan (c = 10.28 m + 6 = 16.28):
;;   move wp-entrance wp-ob (2.37); take_object ob wp-ob      ; frees the paths to wp-o1
;;   move wp-ob wp-removal (1.79); drop_object ob wp-removal  ; stratum 3
;;   move_back wp-removal wp-o2 (0.67)                        ; stratum 3
;;   take_object o2 wp-o2; move wp-o2 wp-container (1.80)
;;   deliver_it o2 container-a wp-container kitchen
;;   move wp-container wp-o1 (1.33); take_object o1 wp-o1
;;   move wp-o1 wp-tray (2.32); deliver_it o1 tray1 wp-tray food
;; p = 0.95^3 * 0.98^2 * 0.98 (drop) = 0.8070, c + 1000(1 - p) = 209.33.

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
    ;; known collision-free paths h(x,y) and their lengths k(x,y) in metres
    (path wp-entrance wp-removal) (= (distance wp-entrance wp-removal) 0.58)
    (path wp-entrance wp-tray) (= (distance wp-entrance wp-tray) 2.40)
    (path wp-entrance wp-container) (= (distance wp-entrance wp-container) 2.86)
    (path wp-entrance wp-ob) (= (distance wp-entrance wp-ob) 2.37)
    (path wp-entrance wp-o1) (= (distance wp-entrance wp-o1) 3.61)
    (path wp-entrance wp-o2) (= (distance wp-entrance wp-o2) 1.25)
    (path wp-removal wp-entrance) (= (distance wp-removal wp-entrance) 0.58)
    (path wp-removal wp-tray) (= (distance wp-removal wp-tray) 2.01)
    (path wp-removal wp-container) (= (distance wp-removal wp-container) 2.33)
    (path wp-removal wp-ob) (= (distance wp-removal wp-ob) 1.79)
    (path wp-removal wp-o1) (= (distance wp-removal wp-o1) 3.02)
    (path wp-removal wp-o2) (= (distance wp-removal wp-o2) 0.67)
    (path wp-tray wp-entrance) (= (distance wp-tray wp-entrance) 2.40)
    (path wp-tray wp-removal) (= (distance wp-tray wp-removal) 2.01)
    (path wp-tray wp-container) (= (distance wp-tray wp-container) 1.00)
    (path wp-tray wp-ob) (= (distance wp-tray wp-ob) 1.84)
    (path wp-tray wp-o1) (= (distance wp-tray wp-o1) 2.32)
    (path wp-tray wp-o2) (= (distance wp-tray wp-o2) 1.75)
    (path wp-container wp-entrance) (= (distance wp-container wp-entrance) 2.86)
    (path wp-container wp-removal) (= (distance wp-container wp-removal) 2.33)
    (path wp-container wp-tray) (= (distance wp-container wp-tray) 1.00)
    (path wp-container wp-ob) (= (distance wp-container wp-ob) 1.26)
    (path wp-container wp-o1) (= (distance wp-container wp-o1) 1.33)
    (path wp-container wp-o2) (= (distance wp-container wp-o2) 1.80)
    (path wp-ob wp-entrance) (= (distance wp-ob wp-entrance) 2.37)
    (path wp-ob wp-removal) (= (distance wp-ob wp-removal) 1.79)
    (path wp-ob wp-tray) (= (distance wp-ob wp-tray) 1.84)
    (path wp-ob wp-container) (= (distance wp-ob wp-container) 1.26)
    (path wp-ob wp-o1) (= (distance wp-ob wp-o1) 1.27)
    (path wp-ob wp-o2) (= (distance wp-ob wp-o2) 1.12)
    (path wp-o1 wp-entrance) (= (distance wp-o1 wp-entrance) 3.61)
    (path wp-o1 wp-removal) (= (distance wp-o1 wp-removal) 3.02)
    (path wp-o1 wp-tray) (= (distance wp-o1 wp-tray) 2.32)
    (path wp-o1 wp-container) (= (distance wp-o1 wp-container) 1.33)
    (path wp-o1 wp-ob) (= (distance wp-o1 wp-ob) 1.27)
    (path wp-o1 wp-o2) (= (distance wp-o1 wp-o2) 2.36)
    (path wp-o2 wp-entrance) (= (distance wp-o2 wp-entrance) 1.25)
    (path wp-o2 wp-removal) (= (distance wp-o2 wp-removal) 0.67)
    (path wp-o2 wp-tray) (= (distance wp-o2 wp-tray) 1.75)
    (path wp-o2 wp-container) (= (distance wp-o2 wp-container) 1.80)
    (path wp-o2 wp-ob) (= (distance wp-o2 wp-ob) 1.12)
    (path wp-o2 wp-o1) (= (distance wp-o2 wp-o1) 2.36))
  (:goal (and (tidied o1) (tidied o2)))
  (:metric minimize (total-cost)))
