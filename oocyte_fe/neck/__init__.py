"""The narrow-necked micropipette passage (seed 001, Section 3.2, Fig. 5): pipette profile,
suction load, peripheral deformation, the passage driver and the mesh study."""
