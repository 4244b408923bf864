#!/usr/bin/env bash
# Checks that a shared libdcol exports only dcol_* symbols (all of the contract) and has the
# expected SONAME.  Usage: check_symbols.sh LIBRARY SONAME
set -euo pipefail
lib=$1
soname=$2

symbols=$(nm -D --defined-only "$lib" | awk 'NF >= 3 { print $3 }' | sort)
stray=$(grep -v '^dcol_' <<<"$symbols" || true)
if [[ -n "$stray" ]]; then
  echo "FAILED: $lib exports symbols outside the dcol_ namespace:"
  echo "$stray"
  exit 1
fi
for name in dcol_status_string dcol_last_error_message dcol_version dcol_shape_new_sphere \
  dcol_shape_new_ellipsoid dcol_shape_new_polytope dcol_shape_new_box dcol_shape_new_capsule \
  dcol_shape_new_cylinder dcol_shape_new_cone dcol_shape_new_polygon dcol_shape_new_halfspace \
  dcol_shape_free \
  dcol_options_default dcol_proximity dcol_gradient dcol_jacobian dcol_distance \
  dcol_distance_gradient dcol_alpha_below dcol_intersect dcol_derivatives dcol_gradient_mrp \
  dcol_jacobian_mrp dcol_proximity_batch dcol_scene_new dcol_scene_free dcol_scene_add \
  dcol_scene_set_pose dcol_scene_size dcol_scene_pairs_within dcol_signed_distance dcol_contacts \
  dcol_proximity_cached dcol_gradient_cached dcol_jacobian_cached dcol_derivatives_cached \
  dcol_distance_cached dcol_distance_gradient_cached dcol_signed_distance_cached \
  dcol_contacts_cached dcol_intersect_cached; do
  if ! grep -qx "$name" <<<"$symbols"; then
    echo "FAILED: $lib does not export $name"
    exit 1
  fi
done

actual=$(readelf -d "$lib" | sed -n 's/.*(SONAME).*\[\(.*\)\].*/\1/p')
if [[ "$actual" != "$soname" ]]; then
  echo "FAILED: SONAME of $lib is '$actual', expected '$soname'"
  exit 1
fi
echo "$(wc -l <<<"$symbols") dcol_ symbols exported, SONAME $actual"
