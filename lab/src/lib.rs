//! The measurement lab (the `shadeballs-lab` crate, not published): the benchmark harness
//! ([`mod@bench`]), the random-walk truth study ([`truth`]) and the picture comparison
//! ([`compare`]), with their PNG plots ([`plot`]) and the `shadeballs-lab` command line
//! ([`cli`]). It imports the library (`shadeballs`); the library never imports it.

pub mod bench;
pub mod cli;
pub mod compare;
pub mod plot;
pub mod truth;
