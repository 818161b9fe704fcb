# Writes OUT (spam_commit.h) with the source's git commit, "-dirty" when the work tree has
# changes, at every build: the version line of a checkpoint (checkpoint_save.c) must name
# the code that wrote it, not the commit of the last configure. The file is rewritten only
# when the line changes, so an unchanged tree rebuilds nothing.
execute_process(COMMAND git describe --always --dirty --abbrev=12 WORKING_DIRECTORY ${SRC}
  OUTPUT_VARIABLE commit OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR commit STREQUAL "")
  set(commit "unknown")
endif()
set(line "#define SPAM_GIT_COMMIT \"${commit}\"\n")
if(EXISTS ${OUT})
  file(READ ${OUT} old)
endif()
if(NOT old STREQUAL line)
  file(WRITE ${OUT} "${line}")
endif()
