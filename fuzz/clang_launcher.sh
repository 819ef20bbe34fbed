#!/bin/sh
# Compiler and linker launcher of the fuzz targets (fuzz/CMakeLists.txt): CMake
# hands over the project's compiler command; this runs the same command with
# clang and libFuzzer's instrumentation instead, so that a gcc build gets the
# fuzzers with every include path, definition and library CMake computed.
#   clang_launcher.sh CLANG MODE COMPILER ARGS...   (MODE: compile or link)
clang="$1"
mode="$2"
shift 3
if [ "$mode" = link ]; then
  flags="-fsanitize=fuzzer,address,undefined"
else
  # -O1 -g after the build type's flags: the later -O wins.
  flags="-O1 -g -fno-omit-frame-pointer -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined"
fi
if [ "$mode" = compile ] && command -v ccache >/dev/null 2>&1; then
  # As for the project's own compiles (CMakeLists.txt): shared between checkouts.
  CCACHE_BASEDIR="$(cd "$(dirname "$0")/.." && pwd)"
  export CCACHE_BASEDIR CCACHE_NOHASHDIR=1
  exec ccache "$clang" "$@" $flags
fi
exec "$clang" "$@" $flags
