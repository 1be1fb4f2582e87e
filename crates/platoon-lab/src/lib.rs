//! platoon-lab: what measures platoon rather than embeds it. The balance bench
//! ([`balance_bench`]), the living-scene bench ([`dynamic_bench`]), the CPU comparison of BVH
//! layouts ([`layout_bench`]), the accuracy-vs-time trade-off tool ([`tradeoff`]) and their plots
//! ([`plot`]). The `platoon` command line runs them (`platoon bench kernel|dynamic|game|balance`,
//! `platoon tradeoff`);
//! the embedding API (`platoon`) knows nothing of them and needs no argument parser.

pub mod balance_bench;
pub mod dynamic_bench;
pub mod layout_bench;
pub mod plot;
pub mod tradeoff;
