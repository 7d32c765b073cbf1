"""The physics of one viscoelastic contact (the bottom layer with
_support: imports nothing else of viscontact).

What it owns: the laws (:mod:`.laws`, the one registry: name, exponent p, parameters, history
each law needs), the force arithmetic (:mod:`.kernels`, compiled by numba, and
:mod:`.kernels_py`, the same source run as plain Python), the domain of every parameter
(:mod:`.domain`), and the physical description of a pair (:mod:`.pair`: m*, R*, E*, k_Hertz,
the time scale T, the damping prefactor c and the undamped Hertz contact time
t_c = 3.2180654597 T), after Jian et al., Powder Technol. 356 (2019) 735, eqs. 1-7.
"""
