# The Python package cga_rigid_sim (python/), installed into the devel space by catkin's
# catkin_python_setup() (CMakeLists.txt); its compiled part _core is built by CMake.
from setuptools import setup

from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(
    packages=['cga_rigid_sim', 'cga_rigid_sim.sysid'],
    package_dir={'': 'python'},
))
