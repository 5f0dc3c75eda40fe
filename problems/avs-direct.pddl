;; avs-direct: avs-indirect with one prior changed: kitchens here seldom have a table
;; (P(table IN kitchen) = 0.2 instead of 0.9; think of a kitchen with counters only).
;; Everything else is the same: robot in the corridor at place0, placeholder place1
;; probably leads to a kitchen, room2 of unknown category. Goal: report a cerealbox.
;; R = 1000. Now the direct search of the kitchen wins.
;;
;; Expected plan (direct search):
;;   assume-leads-to-room place1 new-room1 kitchen                            p 0.6
;;   assume-obj-exists-in cerealbox new-room1 kitchen new-object1             p 0.3
;;   move place0 place1                                            c 6
;;   create-viewcones-in cerealbox new-room1 place1                c 1
;;   search-for-object-in cerealbox new-room1 new-object1 place1   c 10       p 0.8
;;   report-position new-object1 cerealbox                         c 1
;; (assumptions may come anywhere before the actions that need them; either virtual
;; object may stand for the cerealbox)
;;
;; c(pi) + R(1 - p(pi)) of the competing plans, by hand:
;;   direct via place1 (above): c = 6+1+10+1 = 18,
;;       p = 0.6*0.3*0.8 = 0.144                  -> 18 + 1000*0.856   = 874.00   BEST
;;   indirect via place1 (table, then cerealbox on it): c = 6+1+10+1+3+1 = 22,
;;       p = 0.6*0.2*0.7*0.8*0.8 = 0.05376        -> 22 + 946.24       = 968.24
;;   direct via room2 assumed kitchen: c = 16, p = 0.2*0.3*0.8 = 0.048 -> 968.00
;;   indirect via room2 assumed office: c = 20, p = 0.7*0.8*0.1*0.64 = 0.03584
;;                                                -> 20 + 964.16       = 984.16
;;   direct in the corridor: c = 12, p = 0.02*0.8 = 0.016 -> 996.00
;;   indirect via room2 assumed kitchen: c = 20, p = 0.2*0.2*0.7*0.64 = 0.01792 -> 1002.08
;; With a table unlikely, the detour through it (0.2*0.7 = 0.14, times a second 0.8)
;; is worth less than a direct look for the cerealbox (0.3).

(define (problem avs-direct)
  (:domain avs)
  (:objects
    place0 place1 place2 - place
    room1 room2 - room
    corridor kitchen office - category
    table cerealbox - class)
  (:virtual-objects new-room1 - room new-object1 new-object2 - thing)
  (:init
    (= (total-cost) 0)
    (robot-at place0)
    (room-known room1) (place-in place0 room1)
    (room-category room1 corridor) (category-known room1)
    (room-known room2) (place-in place2 room2)
    (category-prior room2)                               ; category not yet known
    (placeholder place1)
    (connected place0 place1) (= (distance place0 place1) 6)
    (connected place1 place0) (= (distance place1 place0) 6)
    (connected place0 place2) (= (distance place0 place2) 4)
    (connected place2 place0) (= (distance place2 place0) 4)
    (support-class table)
    ;; P_category(placeholder): place1 is behind a door hypothesis
    (= (p-leads-to place1 kitchen) 0.6)
    (= (p-leads-to place1 office) 0.3)
    (= (p-leads-to place1 corridor) 0.1)
    ;; P_category(room2)
    (= (p-category room2 kitchen) 0.2)
    (= (p-category room2 office) 0.7)
    (= (p-category room2 corridor) 0.1)
    ;; P(ObjectAt IN a room of category c)
    (= (p-in table kitchen) 0.2)                         ; was 0.9 in avs-indirect
    (= (p-in table office) 0.8)
    (= (p-in table corridor) 0.1)
    (= (p-in cerealbox kitchen) 0.3)
    (= (p-in cerealbox office) 0.05)
    (= (p-in cerealbox corridor) 0.02)
    ;; P(ObjectAt ON a table in a room of category c)
    (= (p-on cerealbox table kitchen) 0.7)
    (= (p-on cerealbox table office) 0.1)
    (= (p-on cerealbox table corridor) 0.1))
  (:goal (reported cerealbox))
  (:goal-reward 1000)
  (:metric minimize (total-cost)))
