# The replay page in headless Chromium (tests/viewer/run_viewer_test.sh).
# Included from tests/CMakeLists.txt. Skipped (77) when Chromium or
# viewer/node_modules is missing, unless CI=true. The screenshot is written to
# <build>/tests/viewer/replay.png.
add_test(NAME viewer_replay
         COMMAND bash ${PROJECT_SOURCE_DIR}/tests/viewer/run_viewer_test.sh $<TARGET_FILE:robophi>
                 ${CMAKE_CURRENT_BINARY_DIR}/viewer)
set_tests_properties(viewer_replay PROPERTIES LABELS viewer SKIP_RETURN_CODE 77 TIMEOUT 300)

# The robots as they look (URDF meshes), the joint plot in the URDF's q and an
# interrupted run's page (tests/viewer/run_robots_test.sh).
add_test(NAME viewer_robots
         COMMAND bash ${PROJECT_SOURCE_DIR}/tests/viewer/run_robots_test.sh $<TARGET_FILE:robophi>
                 ${CMAKE_CURRENT_BINARY_DIR}/viewer)
set_tests_properties(viewer_robots PROPERTIES LABELS viewer SKIP_RETURN_CODE 77 TIMEOUT 600
                     ENVIRONMENT "ROBOPHI_ROBOTS_DIR=${ROBOPHI_ROBOTS_DIR}")

# The live view (robophi run --live, tests/viewer/run_live_test.sh): frames per
# second, pause and resume, a drag's work in summary.json (the pendulum's bob, and a
# rigid iiwa's link), and the state hash of a live run without drag equal to the
# plain run's. About 20 s.
add_test(NAME viewer_live
         COMMAND bash ${PROJECT_SOURCE_DIR}/tests/viewer/run_live_test.sh $<TARGET_FILE:robophi>
                 ${CMAKE_CURRENT_BINARY_DIR}/viewer)
set_tests_properties(viewer_live PROPERTIES LABELS viewer SKIP_RETURN_CODE 77 TIMEOUT 300
                     ENVIRONMENT "ROBOPHI_ROBOTS_DIR=${ROBOPHI_ROBOTS_DIR}")

# The Panda pick, the Husky drive, the iiwa and the UR5 at t = 0 and at a later
# time against the reference images tests/viewer/reference/*.png, with a tolerance
# (tests/viewer/run_reference_test.sh; ROBOPHI_RECORD_REFERENCE=1 re-records).
add_test(NAME viewer_reference
         COMMAND bash ${PROJECT_SOURCE_DIR}/tests/viewer/run_reference_test.sh $<TARGET_FILE:robophi>
                 ${CMAKE_CURRENT_BINARY_DIR}/viewer)
set_tests_properties(viewer_reference PROPERTIES LABELS viewer SKIP_RETURN_CODE 77 TIMEOUT 600
                     ENVIRONMENT "ROBOPHI_ROBOTS_DIR=${ROBOPHI_ROBOTS_DIR}")
