//! Tests of the collision set and the potential.
