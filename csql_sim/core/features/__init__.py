"""Features the learner builds from a domain's predicates: a description-logic grammar over them."""
