//! A dynamic bounding-volume tree (being written).
