// The unit the test programs' precompiled headers are built from (tests/CMakeLists.txt,
// roverlab_test_pch); it compiles to nothing else.
