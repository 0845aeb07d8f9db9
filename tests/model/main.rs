//! The model against answers from outside the code: closed forms, the paper's figures,
//! measured data, and the stiff and extreme cases the solver must survive.
//!
//! One test binary for the group (linking one binary instead of one per file): each file
//! below is a module, the helpers they share are the modules at the top.

#[path = "../analytic/mod.rs"]
mod analytic;
#[path = "../common/mod.rs"]
mod common;
#[path = "../contact_common/mod.rs"]
mod contact_common;

mod bending;
mod bias_extension;
mod box_newton;
mod capstan;
mod contact_balance;
mod contact_checks;
mod developed_view;
mod double_dome_tools;
mod drape_predictor;
mod drawing_checks;
mod element_checks;
mod ellipsoid_undulation;
mod figure11_box;
mod figure6;
mod frontier_grid;
mod holder_pull_out;
mod law_reference;
mod levels;
mod membrane_force;
mod mesh_distance;
mod mesh_exactness;
mod shear_law;
mod solver_checks;
mod stability;
mod step_balance;
mod stl_files;
mod tools_checks;
mod wrinkles;
