from glob import glob

from setuptools import find_packages, setup

PACKAGE = 'biped_mpc'

setup(
    name=PACKAGE,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    package_data={PACKAGE: ['robots/*']},
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + PACKAGE]),
        ('share/' + PACKAGE, ['package.xml']),
        ('share/' + PACKAGE + '/config', glob('config/*.yaml')),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    description=('Three-mass and LIPM models, linear MPC, state estimator and inverse '
                 'kinematics of the biped stack.'),
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'mpc_controller = biped_mpc.nodes.mpc_controller:main',
        ],
    },
)
