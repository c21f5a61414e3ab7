# The layout is the architecture (CONVENTIONS: layout). Fails when
#   - a file under nodes/ includes the TBB flow graph, yaml-cpp, spdlog, CLI11 or the engine: nodes are pure;
#   - a file under engine/ includes a geometry header or calls geometry (kd-trees, bounding boxes, ICP, nearest
#     neighbours, subsets, transforms): the engine wires nodes and writes outputs; every decision about points is a
#     node function's.
file(GLOB_RECURSE files ${ROOT}/nodes/*.h ${ROOT}/nodes/*.cpp)
set(bad "")
foreach(f ${files})
  file(STRINGS ${f} lines REGEX "^#include")
  foreach(l ${lines})
    if(l MATCHES "flow_graph|tbb/flow|yaml-cpp|spdlog|engine/|CLI/")
      list(APPEND bad "${f}: ${l}")
    endif()
  endforeach()
endforeach()
list(LENGTH files n)
if(n EQUAL 0)
  message(FATAL_ERROR "no files found under ${ROOT}/nodes")
endif()

file(GLOB_RECURSE engine_files ${ROOT}/engine/*.h ${ROOT}/engine/*.cpp)
list(LENGTH engine_files n_engine)
if(n_engine EQUAL 0)
  message(FATAL_ERROR "no files found under ${ROOT}/engine")
endif()
# Headers of geometry the engine has no use for, and calls that do geometry (word boundary before the name).
set(geometry_includes "nodes/core/kdtree\\.h|nanoflann|flann/|pcl/|Eigen/Geometry|ceres/|lemon/")
set(geometry_calls "bounding_box|KdTree|nearest_each|nearest|knn|radius_search|icp|covered_samples|subset|transformed|make_revolution|surface_area|random_surface_points")
foreach(f ${engine_files})
  file(STRINGS ${f} lines)
  foreach(l ${lines})
    string(REGEX REPLACE "//.*$" "" code "${l}")
    if(code MATCHES "^#include.*(${geometry_includes})")
      list(APPEND bad "${f}: geometry header: ${l}")
    elseif(code MATCHES "(^|[^A-Za-z0-9_])(${geometry_calls})[ ]*[(<]")
      list(APPEND bad "${f}: geometry call: ${l}")
    endif()
  endforeach()
endforeach()

if(bad)
  string(REPLACE ";" "\n" bad "${bad}")
  message(FATAL_ERROR "the layout is broken (nodes/ must stay pure, engine/ must not do geometry):\n${bad}")
endif()
message(STATUS "checked ${n} files under nodes/ (no flow graph, YAML, logging or engine includes) and ${n_engine} "
               "under engine/ (no geometry)")
