# Runs CMD (a ;-list) and passes only if it exits non-zero AND its output matches REGEX:
# a bad input must fail with a message that says what is wrong, not crash or succeed.
execute_process(COMMAND ${CMD} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0)
    message(FATAL_ERROR "expected a non-zero exit, got 0:\n${out}${err}")
endif()
if(NOT "${out}${err}" MATCHES "${REGEX}")
    message(FATAL_ERROR "exit ${rc}, but the message does not match '${REGEX}':\n${out}${err}")
endif()
message(STATUS "exit ${rc}: ${err}")
