# Runs `npm ci` in viewer/ when node_modules lacks the three.js that
# package-lock.json pins, then touches STAMP. Invoked by viewer/CMakeLists.txt:
#   cmake -DVIEWER_DIR=... -DNPM=... -DSTAMP=... -P npm_ci_if_needed.cmake
file(READ "${VIEWER_DIR}/package-lock.json" lock)
string(JSON wanted GET "${lock}" packages node_modules/three version)
set(installed "")
if(EXISTS "${VIEWER_DIR}/node_modules/three/package.json")
  file(READ "${VIEWER_DIR}/node_modules/three/package.json" manifest)
  string(JSON installed GET "${manifest}" version)
endif()
if(NOT installed STREQUAL wanted)
  if(NOT NPM)
    message(FATAL_ERROR "viewer: three ${wanted} is not installed in ${VIEWER_DIR}/node_modules "
                        "and npm was not found; run scripts/install-deps.sh")
  endif()
  message(STATUS "viewer: npm ci (three ${wanted}; found '${installed}')")
  execute_process(COMMAND "${NPM}" ci --prefix "${VIEWER_DIR}" --no-audit --no-fund
                  RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "viewer: npm ci --prefix ${VIEWER_DIR} failed (${result})")
  endif()
endif()
file(TOUCH "${STAMP}")
