"""A safe lower bound on the least collapse multiplier, and proofs of the global minimum."""
