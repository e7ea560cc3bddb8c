from glob import glob

from setuptools import find_packages, setup

PACKAGE = 'biped_sim'

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
    description='PyBullet humanoid and three-mass model plant simulators of the biped stack.',
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'simulator = biped_sim.nodes.simulator:main',
        ],
    },
)
