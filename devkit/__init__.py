"""Development kit shared by tests/ and bench/ (never shipped in the add-on).

  paths     the repository, ../shared beside it, the build folder
  binding   addon/core/native.py, the one ctypes binding of the C ABI (the
            add-on's bpy-free core, imported as the package addon.core)
  meshes    generated meshes: exact developable surfaces, noisy ones, the
            paper's models, the run command's demo meshes, benchmark families
  families  seeded random developables of issue 11 with their noise-free twins
  objects   seeded random closed objects (blobs, rounded boxes, tori, limbs)
  measures  angle defects, flat share, turned faces, sharpened edges
  obj       OBJ reading and writing
  tool      the command-line tool on arrays (write, run with --report, read back)
  distance  point-to-triangle distance and the sampled Hausdorff distance
  machine   what a benchmark page says about the machine and the build
  blender   numpy arrays -> Blender objects (only inside Blender)

Tests get it on sys.path from tests/conftest.py, bench scripts and the batch
script insert the repository root themselves."""
