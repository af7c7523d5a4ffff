//! A bounding volume hierarchy over k-DOPs. It knows bounding volumes and leaf ids only; the
//! work at the leaves is passed in.
