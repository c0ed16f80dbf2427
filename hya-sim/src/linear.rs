//! Linear analysis of the observers and of each joint's loop (being written).
