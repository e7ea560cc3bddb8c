from glob import glob

from setuptools import find_packages, setup

PACKAGE = 'biped_planner'

setup(
    name=PACKAGE,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + PACKAGE]),
        ('share/' + PACKAGE, ['package.xml']),
        ('share/' + PACKAGE + '/config', glob('config/*.yaml')),
        ('share/' + PACKAGE + '/maps', glob('maps/*.yaml') + glob('maps/*.pgm')),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    description=('Walking state machine, A* and footstep planner, step timing and walking '
                 'references of the biped stack.'),
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'state_machine = biped_planner.nodes.state_machine:main',
            'footstep_planner = biped_planner.nodes.footstep_planner:main',
            'reference_generator = biped_planner.nodes.reference_generator:main',
            'map_server = biped_planner.nodes.map_server:main',
        ],
    },
)
