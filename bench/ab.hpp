#pragma once
/// \file ab.hpp
/// For the sources of scripts/ab.sh (old against new headers in one benchmark process): AB_TAG, the prefix of every
/// benchmark name ("old/" or "new/", set by ab.sh on the command line; empty in a standalone build). Such a source
/// names its benchmarks `AB_TAG "algorithm/model/tree"`, keeps its functions in an anonymous namespace and defines
/// no main (ab.sh links Google Benchmark's).
#ifndef AB_TAG
#define AB_TAG ""
#endif
