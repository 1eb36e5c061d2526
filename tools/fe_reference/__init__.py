"""CalculiX (ccx) finite-element reference for pdcontact's sphere-on-plane scene.

Meshes the sphere with gmsh (graded toward the contact), writes the CalculiX deck, runs
ccx with face-to-face penalty contact against a rigid plane, recovers each surface node's
normal contact force and computes the project's three accuracy figures against Hertz.
Run it through tools/fe_reference.sh; docs/FE_REFERENCE.md describes the model.
"""
