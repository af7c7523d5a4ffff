//! Discrete oriented polytopes (k-DOPs): bounding volumes with k/2 fixed slab directions.
