"""What the damping law changes in many-particle flows: the many-particle DEM study
(layer 7: may import every package but cli).

Modules: :mod:`.theory` (Haff's law, late-time exponents, the exact bounce sequence),
:mod:`.bounce` (a lacrosse ball bouncing to rest), :mod:`.gas` (a freely cooling granular
gas), :mod:`.flow` (collapse of a granular column), :mod:`.engine` (the contact lines of each
calibrated law and running LAMMPS), :mod:`.report` and :mod:`.figures` (``viscontact
dem-study``).  The LAMMPS inputs are plain LAMMPS scripts in ``inputs/``.
"""
