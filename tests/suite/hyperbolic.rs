//! Tests of this area (filled by its owner).
