//! What the bench measures beyond a scene's Table 1 row, each a section of `report.json`: the
//! accuracy under every map (`accuracy`), how every cost grows with objects and vertices
//! (`scaling`), a precompute whole and sharded (`distributed`), and the machine itself
//! (`machine`).

pub mod accuracy;
pub mod distributed;
pub mod machine;
pub mod scaling;
