# brdfit's versions, all from project(VERSION) in CMakeLists.txt (docs/releasing.md):
#  - BRDFIT_SOVERSION: the shared library's soname (libbrdfit.so.N) and the Debian library
#    package (libbrdfitN); it changes only when a release breaks the ABI;
#  - BRDFIT_GIT_DESCRIPTION: `git describe --always --dirty` when the build is configured
#    in a git checkout, else BRDFIT_GIT_DESCRIPTION_FALLBACK (scripts/package.sh builds a
#    copy of the tree without .git), else empty; shown beside the version, never instead;
#  - BRDFIT_VERSION_FULL: "0.1.0" or "0.1.0 (git DESCRIPTION)", what bf_version() and
#    every command's --version print.
# A commit or checkout updates logs/HEAD, which re-runs the configuration; a change to
# uncommitted files ("-dirty") shows at the next one.
set(BRDFIT_SOVERSION 0)
set(BRDFIT_GIT_DESCRIPTION_FALLBACK "" CACHE STRING "The git description where the source has no .git")
set(BRDFIT_GIT_DESCRIPTION "")
if(BRDFIT_GIT_DESCRIPTION_FALLBACK MATCHES "^[A-Za-z0-9._+-]+$")
  set(BRDFIT_GIT_DESCRIPTION ${BRDFIT_GIT_DESCRIPTION_FALLBACK})
endif()
find_package(Git QUIET)
if(GIT_FOUND AND EXISTS ${PROJECT_SOURCE_DIR}/.git)
  execute_process(COMMAND ${GIT_EXECUTABLE} describe --always --dirty
                  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR} RESULT_VARIABLE git_rc
                  OUTPUT_VARIABLE git_rev OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(git_rc EQUAL 0 AND git_rev MATCHES "^[A-Za-z0-9._+-]+$")
    set(BRDFIT_GIT_DESCRIPTION ${git_rev})
    execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --path-format=absolute --git-path logs/HEAD
                    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR} OUTPUT_VARIABLE git_log
                    OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    if(git_log AND EXISTS ${git_log})
      set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${git_log})
    endif()
  endif()
endif()
if(BRDFIT_GIT_DESCRIPTION)
  set(BRDFIT_VERSION_FULL "${PROJECT_VERSION} (git ${BRDFIT_GIT_DESCRIPTION})")
else()
  set(BRDFIT_VERSION_FULL ${PROJECT_VERSION})
endif()
