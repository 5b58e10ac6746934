//! The measurement lab (feature `lab`): the benchmark harness ([`mod@bench`]) and the
//! random-walk truth study ([`truth`]), with their PNG plots ([`plot`]). It imports the
//! library; the library never imports it.

pub mod bench;
pub mod compare;
pub mod plot;
pub mod truth;
