//! The a-priori bounds, before flying: the tight bounds by interval arithmetic ([`tight`]), the
//! certificate evaluated with them beside the paper's ([`certificate`]) and the `host-sim bounds`
//! table ([`table`]).

pub mod certificate;
pub mod memo;
pub mod table;
pub mod tight;
