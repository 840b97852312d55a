//! The library half of the `horus-ros` command-line tool: what its fuzz targets and tests reach
//! without going through the binary. The binary (`src/main.rs`) is the tool itself.

#[doc(hidden)]
pub mod dynamic;
