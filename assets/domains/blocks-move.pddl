; The blocks world without a hand: one operator, move(?b, ?from, ?to), with the table an object.
; The table is always clear: putting a block on it does not make it busy.
(define (domain blocks-move)
  (:requirements :strips :equality :conditional-effects)
  (:constants table)
  (:predicates (on ?x ?y) (clear ?x) (block ?x))
  (:action move
    :parameters (?b ?from ?to)
    :precondition (and (block ?b) (clear ?b) (on ?b ?from) (clear ?to) (not (= ?b ?to)) (not (= ?from ?to)))
    :effect (and (on ?b ?to) (not (on ?b ?from)) (clear ?from)
                 (when (block ?to) (not (clear ?to))))))
