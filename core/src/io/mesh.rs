//! Tube meshes (generalised cylinders, SPEC §1.3) and their OBJ / VTK export. (To be written.)
