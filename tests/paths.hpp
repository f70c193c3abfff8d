// The checkout's files the tests and benchmarks read as data, with their absolute paths in one
// generated file (paths.cpp.in): no other object holds the checkout's path, so a compiler cache
// shares them between clones.
#pragma once

namespace sscape_paths {

// model_format/models/sscape-default.sscape: the shipped default model's file.
const char* default_model_file();

// The build tree's folder the test binary works in (test_main.cpp): the files the tests write.
const char* scratch_folder();

}  // namespace sscape_paths
