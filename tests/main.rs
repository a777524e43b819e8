//! tribo's test suite, one binary so that the heavy dependencies link once.

mod bad_input;
mod browser;
mod cli;
mod common;
mod contact;
mod elasticity;
mod figures;
mod forming;
mod forming_report;
mod full_tier;
mod merge;
mod mesh;
mod mesh_limits;
mod model_contact;
mod model_fluid;
mod model_grid;
mod notes;
mod open_data;
mod outputs;
mod own_scenes;
mod properties;
mod report_failures;
mod reynolds;
mod substokes;
mod uzawa;
mod warnings;
