;; avs.pddl: active visual search (Göbelbecker, Aydemir, Pronobis, Sjöö, Jensfelt,
;; "A Planning Approach to Active Visual Search in Large Environments"),
;; in the tidyplan dialect.
;;
;; The robot looks for an object of a class (a cerealbox) in a partly unknown building.
;; What it does not know is assumed, by assumptive actions (Definition 1): for
;; P(X = x | Y), the precondition holds Y and "X not yet known", the effect sets X = x
;; and "X known", and the probability is P(X = x | Y). Assumptions cost nothing; they
;; are checked by the execution monitor, not executed.
;;
;;   assume-leads-to-room   placeholder ?p leads to a new room of category ?c
;;                          (binds a virtual room; P_category(placeholder))
;;   assume-category        a known room has category ?c (P_category(room))
;;   assume-obj-exists-in   an object of class ?cl is IN a room of category ?c
;;                          (binds a virtual thing; P(ObjectAt L^C), L = the room)
;;   assume-obj-exists-on   an object of class ?cl is ON an object of class ?bcl in a
;;                          room of category ?c (binds a virtual thing; indirect search,
;;                          Garvey 1976: find a table first, then the cerealbox on it)
;;
;; Physical actions: move (cost = distance in metres), create-viewcones-in/-on (cost 1),
;; search-for-object-in (cost 10: view cones over a whole room) and -on (cost 3: a
;; table top), both with p = 0.8 (the paper's false negative rate 0.2), and
;; report-position (cost 1). The paper's CREATEVIEWCONES and SEARCHFOROBJECT take the
;; location as "IN room" or "ON object"; here each is split into two schemas.
;; The decision-theoretic planner behind SEARCHFOROBJECT is abstracted into that one
;; action with its success probability.
;;
;; Conventions for problems: every real room has (room-known ?r); every real object
;; (thing-known ?o), (of-class ...), (obj-in ...) and (found ...) once seen, and
;; (exists-in-known ?cl ?r) when the room has been searched for ?cl. Virtual rooms and
;; things (:virtual-objects) have none of these until an assumption binds them.
;; Probabilities p-leads-to, p-category, p-in and p-on are static functions in :init,
;; each in (0, 1]. A planner grounds an assumption for every binding that is reachable
;; when negative preconditions are ignored, so a problem must give: p-leads-to for
;; every placeholder x category, p-in for every class x category, p-on for every
;; class x support class x category (classes differ), and p-category for every
;; category x room marked (category-prior ?r). The static guards `category-prior`
;; and `support-class` keep the planner from grounding assumptions on a virtual room
;; (whose category only assume-leads-to-room sets) or on a non-support class.

(define (domain avs)
  (:requirements :typing :equality :negative-preconditions :action-costs
                 :probabilities :assumptions)

  (:types place room category class thing)

  (:predicates
    (robot-at ?p - place)
    (connected ?from ?to - place)
    (placeholder ?p - place)                     ; frontier of explored space
    (place-in ?p - place ?r - room)
    (leads-known ?p - place)                     ; def(what ?p leads to)
    (room-known ?r - room)                       ; a real room, or a bound virtual one
    (room-category ?r - room ?c - category)
    (category-known ?r - room)                   ; def(category(?r))
    (category-prior ?r - room)                   ; static: p-category is given for ?r
    (thing-known ?o - thing)                     ; a real object, or a bound virtual one
    (of-class ?o - thing ?cl - class)
    (support-class ?cl - class)                  ; things of ?cl can have things ON them
    (obj-in ?o - thing ?r - room)
    (obj-on ?o ?base - thing)
    (exists-in-known ?cl - class ?r - room)      ; def(a ?cl IN ?r)
    (exists-on-known ?cl - class ?base - thing)  ; def(a ?cl ON ?base)
    (viewcones-in ?cl - class ?r - room)
    (viewcones-on ?cl - class ?base - thing)
    (found ?o - thing)
    (reported ?cl - class))

  (:functions
    (total-cost) - number
    (distance ?from ?to - place) - number
    (p-leads-to ?p - place ?c - category) - number      ; P_category(placeholder)
    (p-category ?r - room ?c - category) - number       ; P_category(room)
    (p-in ?cl - class ?c - category) - number           ; P(ObjectAt IN a room of ?c)
    (p-on ?cl ?bcl - class ?c - category) - number)     ; P(ObjectAt ON a ?bcl in ?c)

  ;; ------------------------------------------------------------------ assumptions
  (:assumption assume-leads-to-room
    :parameters (?p - place ?r - room ?c - category)
    :probability (p-leads-to ?p ?c)
    :precondition (and (placeholder ?p)
                       (not (leads-known ?p))
                       (not (room-known ?r)))
    :effect (and (leads-known ?p)
                 (room-known ?r)
                 (place-in ?p ?r)
                 (room-category ?r ?c)
                 (category-known ?r)))

  (:assumption assume-category
    :parameters (?r - room ?c - category)
    :probability (p-category ?r ?c)
    :precondition (and (room-known ?r)
                       (category-prior ?r)
                       (not (category-known ?r)))
    :effect (and (room-category ?r ?c) (category-known ?r)))

  (:assumption assume-obj-exists-in
    :parameters (?cl - class ?r - room ?c - category ?o - thing)
    :probability (p-in ?cl ?c)
    :precondition (and (room-category ?r ?c)
                       (not (exists-in-known ?cl ?r))
                       (not (thing-known ?o)))
    :effect (and (exists-in-known ?cl ?r)
                 (thing-known ?o)
                 (of-class ?o ?cl)
                 (obj-in ?o ?r)))

  (:assumption assume-obj-exists-on
    :parameters (?cl - class ?base - thing ?bcl - class ?c - category ?r - room
                 ?o - thing)
    :probability (p-on ?cl ?bcl ?c)
    :precondition (and (support-class ?bcl)
                       (not (= ?cl ?bcl))
                       (thing-known ?base)
                       (of-class ?base ?bcl)
                       (obj-in ?base ?r)
                       (room-category ?r ?c)
                       (not (exists-on-known ?cl ?base))
                       (not (thing-known ?o)))
    :effect (and (exists-on-known ?cl ?base)
                 (thing-known ?o)
                 (of-class ?o ?cl)
                 (obj-on ?o ?base)))

  ;; ------------------------------------------------------------- physical actions
  (:action move
    :parameters (?from ?to - place)
    :precondition (and (robot-at ?from) (connected ?from ?to))
    :effect (and (robot-at ?to)
                 (not (robot-at ?from))
                 (increase (total-cost) (distance ?from ?to))))

  (:action create-viewcones-in
    :parameters (?cl - class ?r - room ?p - place)
    :precondition (and (robot-at ?p) (place-in ?p ?r))
    :effect (and (viewcones-in ?cl ?r) (increase (total-cost) 1)))

  (:action create-viewcones-on
    :parameters (?cl - class ?base - thing ?r - room ?p - place)
    :precondition (and (robot-at ?p) (place-in ?p ?r) (obj-in ?base ?r) (found ?base))
    :effect (and (viewcones-on ?cl ?base) (increase (total-cost) 1)))

  (:action search-for-object-in
    :parameters (?cl - class ?r - room ?o - thing ?p - place)
    :probability 0.8
    :precondition (and (robot-at ?p)
                       (place-in ?p ?r)
                       (viewcones-in ?cl ?r)
                       (obj-in ?o ?r)
                       (of-class ?o ?cl)
                       (not (found ?o)))
    :effect (and (found ?o) (increase (total-cost) 10)))

  (:action search-for-object-on
    :parameters (?cl - class ?base - thing ?o - thing ?r - room ?p - place)
    :probability 0.8
    :precondition (and (robot-at ?p)
                       (place-in ?p ?r)
                       (obj-in ?base ?r)
                       (viewcones-on ?cl ?base)
                       (obj-on ?o ?base)
                       (of-class ?o ?cl)
                       (not (found ?o)))
    :effect (and (found ?o) (increase (total-cost) 3)))

  (:action report-position
    :parameters (?o - thing ?cl - class)
    :precondition (and (found ?o) (of-class ?o ?cl))
    :effect (and (reported ?cl) (increase (total-cost) 1))))
