;; avs-indirect: Göbelbecker et al.'s first plan (their Sec. 4): the robot is in
;; the middle of a corridor; placeholder place1 (behind a door hypothesis) probably
;; leads to a kitchen; room2 is a known room of unknown category (office-looking).
;; Goal: report the position of a cerealbox. R = 1000.
;;
;; Expected plan (indirect search: find a table, then the cerealbox on it):
;;   assume-leads-to-room place1 new-room1 kitchen                            p 0.6
;;   assume-obj-exists-in table new-room1 kitchen new-object1                 p 0.9
;;   assume-obj-exists-on cerealbox new-object1 table kitchen new-room1 new-object2
;;                                                                            p 0.7
;;   move place0 place1                                            c 6
;;   create-viewcones-in table new-room1 place1                    c 1
;;   search-for-object-in table new-room1 new-object1 place1       c 10       p 0.8
;;   create-viewcones-on cerealbox new-object1 new-room1 place1    c 1
;;   search-for-object-on cerealbox new-object1 new-object2 new-room1 place1
;;                                                                 c 3        p 0.8
;;   report-position new-object2 cerealbox                         c 1
;; (assumptions may come anywhere before the actions that need them, and the virtual
;; objects are interchangeable: a planner may bind new-object2 to the table instead)
;;
;; c(pi) + R(1 - p(pi)) of the competing plans, by hand:
;;   indirect via place1 (above):  c = 6+1+10+1+3+1 = 22,
;;       p = 0.6*0.9*0.7*0.8*0.8 = 0.24192        -> 22 + 1000*0.75808 = 780.08   BEST
;;   direct via place1 (assume cerealbox IN new-room1, create-viewcones-in,
;;       search-for-object-in, report): c = 6+1+10+1 = 18,
;;       p = 0.6*0.3*0.8 = 0.144                  -> 18 + 856.00       = 874.00
;;   indirect via room2 assumed kitchen: c = 4+1+10+1+3+1 = 20,
;;       p = 0.2*0.9*0.7*0.64 = 0.08064           -> 20 + 919.36       = 939.36
;;   direct via room2 assumed kitchen: c = 4+1+10+1 = 16,
;;       p = 0.2*0.3*0.8 = 0.048                  -> 16 + 952.00       = 968.00
;;   direct in the corridor: c = 1+10+1 = 12, p = 0.02*0.8 = 0.016 -> 996.00
;;   (place1 or room2 as an office: p <= 0.7*0.8*0.1*0.64 = 0.036 -> over 960)
;; The indirect plan wins although it costs 4 more: the table is almost certainly in a
;; kitchen and the cerealbox is much likelier on it (0.9*0.7 = 0.63) than found by a
;; direct search of the room (0.3), which outweighs the second search's 0.8.
;; Against the direct plan, the indirect one wins for any R > 4 / (0.24192 - 0.144)
;; = 40.9; at R = 1000 by 93.92.

(define (problem avs-indirect)
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
    (= (p-in table kitchen) 0.9)
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
