"""The analyses, each a function of a model and a state or a time grid, all on the
compiled engine: kinematics, dynamics (forward simulation, inverse dynamics), the time
integrators, statics with load steps, the linearized analyses (vibration modes,
buckling, compliance, state space), free rotations of spatial nodes, and the symbolic
path (SymPy) with the equations it generates."""
