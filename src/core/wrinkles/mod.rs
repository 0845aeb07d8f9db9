//! Wrinkles, beyond the paper: the small pressure pattern that lets a buckle start
//! ([`trigger`]) and the wrinkle amplitude read off the formed part ([`amplitude`]).

pub mod amplitude;
pub mod trigger;
