; Three rooms in a row, doors shut, the store room dark: the robot opens its way, switches the
; store's lamp on (the lamp is reachable once the door is open), and brings each item home.
(define (problem derived-tidy-1)
  (:domain derived-tidy)
  (:objects hall kitchen store - room d1 d2 - door cup book - item lamp0 lamp1 lamp2 - lamp)
  (:init
    (robot-in hall) (hand-empty)
    (door-between d1 hall kitchen) (door-between d1 kitchen hall)
    (door-between d2 kitchen store) (door-between d2 store kitchen)
    (lamp-in lamp0 hall) (on lamp0) (lamp-in lamp2 kitchen) (on lamp2) (lamp-in lamp1 store)
    (item-in cup store) (belongs cup kitchen)
    (item-in book kitchen) (belongs book hall)
    (= (total-cost) 0))
  (:goal (and (tidy) (robot-in hall)))
  (:metric minimize (total-cost)))
