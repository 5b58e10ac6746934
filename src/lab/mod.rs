//! The measurement lab (feature `lab`): the benchmark harness ([`mod@bench`]) and the
//! random-walk truth study ([`truth`]). It imports the library; the library never imports it.

pub mod bench;
pub mod truth;
