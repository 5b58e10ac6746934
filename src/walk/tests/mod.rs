//! The walks' tests that need the crate's internals (moved from the suite, tests/suite).
//! They build with the command line's features only, so `cargo test --no-default-features
//! --lib` does not run them a second time.

mod coating;
