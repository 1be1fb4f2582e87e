//! platoon-lab: what measures platoon rather than embeds it. The balance bench
//! ([`balance_bench`]), the living-scene bench ([`dynamic_bench`]), the CPU comparison of BVH
//! layouts ([`layout_bench`]), each rendering method's own benches ([`method`]: vertex links',
//! layered hit buffers'), the bench scenes against Mitsuba 3 ([`scene_bench`], through the
//! exporter [`mitsuba`]), scenes of production size ([`scale_bench`]), a game's image quality at its frame budget ([`realtime_bench`]), the
//! accuracy-vs-time trade-off tool ([`tradeoff`]) and their plots
//! ([`plot`]). The `platoon` command line runs them (`platoon bench kernel|scenes|scale|dynamic|game|balance|realtime|links|lhb`,
//! `platoon tradeoff`);
//! the embedding API (`platoon`) knows nothing of them and needs no argument parser.

pub mod balance_bench;
pub mod dynamic_bench;
pub mod generated;
pub mod layout_bench;
pub mod method;
pub mod mitsuba;
pub mod plot;
pub mod realtime_bench;
pub mod scale_bench;
pub mod scene_bench;
pub mod shared;
pub mod tearoom;
pub mod tradeoff;
