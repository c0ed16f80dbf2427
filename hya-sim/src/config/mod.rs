//! The configuration, the lowest layer: a scenario as TOML ([`scenario`]); its settings checked
//! once for an arm of `N` joints ([`settings`], lists on [`lists`]), the plant's as types of their
//! kind ([`plant`]); and what running it will cost ([`cost`]). Nothing here knows of the plant,
//! the loop or the metrics.

pub mod cost;
pub mod lists;
pub mod plant;
pub mod scenario;
pub mod settings;
