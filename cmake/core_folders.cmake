# The core's folders, one concept each (doc/architecture.md): src/<folder>/*.cc is compiled into
# the core library, include/cga_rigid_sim/<folder>/ holds its public headers, and
# test/<folder>/ becomes the gtest binary test_<folder>. Read by CMakeLists.txt and
# fuzz/CMakeLists.txt.
set(CGA_RIGID_SIM_CORE_FOLDERS
  cga          # the algebra: multivectors, motors, rotors
  body         # one rigid body: inertia, state, loads, the free flow, the free-body integrators
  tree         # articulated trees: kinematics, ABA, RNEA, mass matrix, momentum, integrators
  curved       # bodies in curved space (1-up)
  scene        # what a scene holds: shapes, meshes, initial states, self-collision rules
  scene/urdf   # reading URDF and SRDF into a scene
  control      # robot control without ROS: trajectories, splines, the trajectory controller, YAML
  contact      # detection, landing, rows, islands, the solver, resting, sleep, tree contacts
  sim          # the World: model, data, compile, the step's stages
  sim/input    # inputs from outside: admission, the queue, efforts, wrenches
  sim/controllers  # the World's joint controllers: loading, commands, the control stage
  sensor)          # sensors read from the World after a step: IMU, odometry, contacts; noise
# Test folders: math/ (header-only kernels) has tests but no sources; test/sim/ includes its
# sub-folder input/, test/scene/ its sub-folder urdf/.
set(CGA_RIGID_SIM_TEST_FOLDERS math cga body tree curved scene control contact sim sensor)

# cga_rigid_sim_core_sources(<out-var> <root> <folder>...): the .cc files of the folders.
function(cga_rigid_sim_core_sources out root)
  set(_globs "")
  foreach(_folder ${ARGN})
    list(APPEND _globs ${root}/src/${_folder}/*.cc)
  endforeach()
  file(GLOB _sources CONFIGURE_DEPENDS ${_globs})
  set(${out} ${_sources} PARENT_SCOPE)
endfunction()
