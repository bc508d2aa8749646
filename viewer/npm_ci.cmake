# Runs `npm ci` in VIEWER_DIR when node_modules is missing or older than package-lock.json.
#   cmake -DNPM=/usr/bin/npm -DVIEWER_DIR=.../viewer -P npm_ci.cmake
set(stamp ${VIEWER_DIR}/node_modules/.package-lock.json)
if(EXISTS ${stamp} AND NOT ${VIEWER_DIR}/package-lock.json IS_NEWER_THAN ${stamp})
  message(STATUS "viewer: node_modules is up to date")
  return()
endif()
message(STATUS "viewer: npm ci in ${VIEWER_DIR}")
execute_process(COMMAND ${NPM} ci --no-audit --no-fund
                WORKING_DIRECTORY ${VIEWER_DIR} RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "viewer: npm ci failed (${status}); the npm registry must be reachable")
endif()
if(NOT EXISTS ${VIEWER_DIR}/node_modules/three/build/three.module.js)
  message(FATAL_ERROR "viewer: npm ci did not install three")
endif()
