//! Studies built on runs: the factor of safety of a scene ([`stability`]) and the
//! verification cases against closed forms and published values ([`verification`]).
pub mod stability;
pub mod verification;
