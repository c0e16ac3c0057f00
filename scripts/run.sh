#!/usr/bin/env bash
# The "run" command: build the engine and the add-on zip, install the zip into
# a private Blender user folder, run the add-on headless on a generated noisy
# curved cone band (like the paper's Fig. 3), save the result as a .blend and
# render before/after pictures coloured by the angle defect.
#
# Blender's own configuration is not touched: BLENDER_USER_SCRIPTS and
# BLENDER_USER_CONFIG point into $BUILD/blender_user, where the add-on is
# installed (bpy.ops.preferences.addon_install) and enabled (saved userpref).
# To use that setup by hand afterwards:
#   BLENDER_USER_SCRIPTS=build/blender_user/scripts BLENDER_USER_CONFIG=build/blender_user/config blender
#
# Output (default out/, or $DEVELOPABLE_OUT_DIR):
#   cone_band.blend        object with shape key "Developable", colour attributes
#                          "Defect Before"/"Defect After", defect_before/after, patch_id
#   cone_band_before.png   Workbench render, colours = angle defect before
#   cone_band_after.png    the same after (same colour scale)
#   cone_band_deformed.obj the deformed mesh
source "$(dirname "$0")/setup.sh"   # sets REPO and BUILD, builds the engine

OUT=${DEVELOPABLE_OUT_DIR:-$REPO/out}
mkdir -p "$OUT"

echo "run: packaging the add-on" >&2
cmake --build "$BUILD" --target addon_zip >&2
ZIP=$(ls -t "$BUILD"/dist/developable_mesh-*.zip | head -n 1)

export BLENDER_USER_SCRIPTS="$BUILD/blender_user/scripts"
export BLENDER_USER_CONFIG="$BUILD/blender_user/config"
rm -rf "$BUILD/blender_user"
mkdir -p "$BLENDER_USER_SCRIPTS" "$BLENDER_USER_CONFIG"
unset DEVELOPABLE_LIBRARY   # use the library shipped inside the zip

BLENDER=(blender --background --python-exit-code 1)

echo "run: installing $ZIP into $BLENDER_USER_SCRIPTS" >&2
"${BLENDER[@]}" --factory-startup --python-expr "
import bpy, sys
bpy.ops.preferences.addon_install(filepath=sys.argv[-1], overwrite=True)
bpy.ops.preferences.addon_enable(module='developable_mesh')
bpy.ops.wm.save_userpref()
" -- "$ZIP" >/dev/null

echo "run: processing the generated cone band" >&2
"${BLENDER[@]}" -P "$REPO/scripts/batch_developable.py" -- \
  demo:cone_band "$OUT/cone_band.blend" --render "$OUT/cone_band" \
  --addon-module developable_mesh --gauss-image | grep -E "^(DEVELOPABLE_RESULT|Info|Error)" || {
  echo "run: the batch run failed" >&2; exit 1; }

echo "run: the headless one-liner on the saved file" >&2
"${BLENDER[@]}" "$OUT/cone_band.blend" --python-expr "
import bpy
bpy.context.view_layer.objects.active = bpy.data.objects['cone_band']
assert bpy.ops.mesh.make_developable() == {'FINISHED'}
ob = bpy.context.active_object
assert [k.name for k in ob.data.shape_keys.key_blocks] == ['Basis', 'Developable']
print('Info: re-run on the saved file ok: E %.4g -> %.4g rad' % (ob.developable.e_before, ob.developable.e_after))
" | grep -E "^(Info|Error)"

"${BLENDER[@]}" -P "$REPO/scripts/batch_developable.py" -- \
  "$OUT/cone_band.blend" "$OUT/cone_band_deformed.obj" --addon-module developable_mesh >/dev/null

echo "run: wrote" >&2
ls -1 "$OUT"/cone_band*
