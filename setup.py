"""Python packaging for slam_predict: used by catkin (catkin_python_setup) and by pip (-e .)."""
from setuptools import find_packages, setup

PACKAGES = find_packages("src")
ENTRY_POINTS = {"console_scripts": ["slam-predict = slam_predict.cli.main:main"]}

try:  # catkin builds: metadata from package.xml
    from catkin_pkg.python_setup import generate_distutils_setup

    ARGS = generate_distutils_setup(packages=PACKAGES, package_dir={"": "src"})
except ImportError:  # plain pip builds
    ARGS = dict(name="slam_predict", version="0.1.0", packages=PACKAGES, package_dir={"": "src"})

ARGS["entry_points"] = ENTRY_POINTS
ARGS["package_data"] = {"slam_predict": ["py.typed"]}
setup(**ARGS)
