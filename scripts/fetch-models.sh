#!/usr/bin/env bash
# Fetches the test/benchmark models into the model cache (nothing is committed to the repository):
#   bunny00.off, ChineseDragon-10kv.off,  CGAL's data set (Debian package libcgal-demo, inside
#   armadillo.off, refined_elephant.off   /usr/share/doc/libcgal-dev/data.tar.gz: data/meshes/)
#   assimp-testmodels/                    assimp's test models (Debian package assimp-testmodels,
#                                         /usr/share/assimp/models), including invalid/
# Cache: $PENUMBRA_MODELS, else $XDG_CACHE_HOME/penumbra/models, else ~/.cache/penumbra/models
# (the same place penumbra::models_dir() looks).
# Needs apt-get and dpkg (Debian/Ubuntu) but no root: the packages are downloaded with
# `apt-get download` and unpacked with `dpkg -x`, never installed. Idempotent: work already done
# is skipped.
set -euo pipefail

DEST="${PENUMBRA_MODELS:-${XDG_CACHE_HOME:-$HOME/.cache}/penumbra/models}"
CGAL_MODELS=(bunny00.off ChineseDragon-10kv.off armadillo.off refined_elephant.off)

say() { echo "fetch-models: $*"; }
die() {
  echo "fetch-models: error: $*" >&2
  exit 1
}

need_cgal=0
for f in "${CGAL_MODELS[@]}"; do
  [ -s "$DEST/$f" ] || need_cgal=1
done
need_assimp=0
[ -f "$DEST/assimp-testmodels/.complete" ] || need_assimp=1

if [ "$need_cgal" -eq 0 ] && [ "$need_assimp" -eq 0 ]; then
  say "all models already in $DEST (nothing to do)"
  exit 0
fi

command -v apt-get >/dev/null || die "apt-get not found (this script needs a Debian/Ubuntu system)"
command -v dpkg >/dev/null || die "dpkg not found (this script needs a Debian/Ubuntu system)"
mkdir -p "$DEST"

WORK="$(mktemp -d "${TMPDIR:-/tmp}/penumbra-models.XXXXXX")"
trap 'rm -rf "$WORK"' EXIT
# apt-get download drops privileges to _apt when run as root; let it write here.
chmod 755 "$WORK"

# Downloads one package's .deb into $WORK and unpacks it into $WORK/<package>.
fetch_deb() {
  local pkg="$1"
  say "downloading $pkg"
  if ! (cd "$WORK" && apt-get download -q "$pkg" >/dev/null 2>"$WORK/apt.log"); then
    if [ "$(id -u)" -eq 0 ]; then
      say "apt-get download $pkg failed; refreshing the package lists (apt-get update)"
      apt-get update -qq >/dev/null || true
      (cd "$WORK" && apt-get download -q "$pkg" >/dev/null 2>"$WORK/apt.log") ||
        die "apt-get download $pkg failed: $(tail -n 1 "$WORK/apt.log")"
    else
      die "apt-get download $pkg failed: $(tail -n 1 "$WORK/apt.log")
  (the package lists may be stale or lack it: run 'sudo apt-get update' and retry)"
    fi
  fi
  local debs=("$WORK"/"${pkg}"_*.deb)
  local deb="${debs[0]}"
  [ -f "$deb" ] || die "apt-get download $pkg produced no .deb"
  mkdir -p "$WORK/$pkg"
  dpkg -x "$deb" "$WORK/$pkg"
}

if [ "$need_cgal" -eq 1 ]; then
  fetch_deb libcgal-demo
  archive="$WORK/libcgal-demo/usr/share/doc/libcgal-dev/data.tar.gz"
  [ -f "$archive" ] || die "libcgal-demo has no usr/share/doc/libcgal-dev/data.tar.gz"
  members=()
  for f in "${CGAL_MODELS[@]}"; do members+=("data/meshes/$f"); done
  mkdir -p "$WORK/cgal"
  tar -xzf "$archive" -C "$WORK/cgal" "${members[@]}" ||
    die "could not extract ${members[*]} from $archive"
  for f in "${CGAL_MODELS[@]}"; do
    if [ -s "$DEST/$f" ]; then
      say "$f already present"
    else
      cp "$WORK/cgal/data/meshes/$f" "$DEST/$f.tmp"
      mv "$DEST/$f.tmp" "$DEST/$f"
      say "installed $DEST/$f"
    fi
  done
else
  say "CGAL models already present"
fi

if [ "$need_assimp" -eq 1 ]; then
  fetch_deb assimp-testmodels
  src="$WORK/assimp-testmodels/usr/share/assimp/models"
  [ -d "$src/invalid" ] || die "assimp-testmodels has no usr/share/assimp/models/invalid"
  rm -rf "$DEST/assimp-testmodels" "$DEST/assimp-testmodels.tmp"
  cp -r "$src" "$DEST/assimp-testmodels.tmp"
  touch "$DEST/assimp-testmodels.tmp/.complete"
  mv "$DEST/assimp-testmodels.tmp" "$DEST/assimp-testmodels"
  say "installed $DEST/assimp-testmodels ($(find "$DEST/assimp-testmodels" -type f | wc -l) files)"
else
  say "assimp test models already present"
fi

say "done: models in $DEST"
