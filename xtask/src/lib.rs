//! The developer tasks of `cargo xtask` as a library (the binary, `main.rs`, parses the command
//! line and calls them): `demo` (the quick start's main job), `bench` (the paper's Table 1 and
//! every measured figure: its sections in `bench`, what they measure in `measure`, the report
//! they write in `report`) and `publish` (the generated docs). The user commands are the `vcuts`
//! crate's.

pub mod bench;
pub mod demo;
pub mod measure;
pub mod publish;
pub mod report;
