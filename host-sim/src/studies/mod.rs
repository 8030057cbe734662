//! What is measured with the run toolkit ([`crate::runs`]): robustness campaigns
//! ([`campaign`]), the paper's design choices ablated ([`ablation`]: hysteresis, filters, the
//! no-dive thrust, the integral action), the law against the baselines ([`compare`]) and the
//! law-rate study ([`rates`]).

pub mod ablation;
pub mod campaign;
pub mod compare;
pub mod rates;
