"""The code of tools/gen-scenes (its usage is in that script's docstring), one module per scene family.

gltf (builder, .gltf/.glb/PNG bytes), vecmath, cornell, sphere, fixtures, solids (leak-scene
helpers), rooms, atrium, stress, animated, sponza; outputs holds the table of written files and main.
"""
