//! pdcontact: peridynamic point-to-surface contact from finite-element meshes.
pub use pdcontact_importers as importers;
