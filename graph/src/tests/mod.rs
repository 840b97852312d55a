//! In-memory tests of the graph cache, with GIDs made from strings as rmw_dds_common's
//! `test/test_graph_cache.cpp` does.

mod actions;
mod display;
mod events;
mod fixtures;
mod index;
mod mutators;
mod queries;
mod services;
mod snapshot;
