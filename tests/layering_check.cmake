# Checks DESIGN.md's layer rules on the sources: which headers each layer may
# include. Run by ctest as `cmake -DROOT=<source dir> -P layering_check.cmake`.
set(rules
  "core|<(Q[A-Za-z]+|vtk[A-Za-z0-9]*\\.h|hdf5\\.h|H5[A-Za-z]*\\.h|nlohmann/|CLI/)|\"(importers|views|app)/"
  "importers|<(Q[A-Za-z]+|vtk[A-Za-z0-9]*\\.h|CLI/)|\"(views|app)/"
  "views|<(Q[A-Za-z]+|hdf5\\.h|H5[A-Za-z]*\\.h|CLI/)|\"(importers|app)/")
set(violations "")
foreach(rule IN LISTS rules)
  string(REPLACE "|" ";" parts "${rule}")
  list(GET parts 0 layer)
  # The pattern is everything after the layer name.
  string(LENGTH "${layer}|" skip)
  string(SUBSTRING "${rule}" ${skip} -1 pattern)
  file(GLOB_RECURSE sources "${ROOT}/${layer}/*.h" "${ROOT}/${layer}/*.cpp")
  foreach(source IN LISTS sources)
    file(STRINGS "${source}" includes REGEX "^[ \t]*#[ \t]*include")
    foreach(line IN LISTS includes)
      if(line MATCHES "#[ \t]*include[ \t]*${pattern}")
        string(APPEND violations "${source}: ${layer}/ must not use: ${line}\n")
      endif()
    endforeach()
  endforeach()
endforeach()
if(violations)
  message(FATAL_ERROR "layering violations:\n${violations}")
endif()
message(STATUS "layering: core, importers and views include only what DESIGN.md allows")
