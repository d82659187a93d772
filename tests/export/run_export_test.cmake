# Driver of the export tests: cmake -DMODE=... -DBRDFFIT=<exe> -DPYTHON=...
# -DNODE=... -DNPM=... -DVALIDATOR=<npm spec> -DNPM_DIR=... -DSOURCE_DIR=...
# -DTEST_DIR=... -DWORK_DIR=... -P run_export_test.cmake. Fails with a
# message naming what was expected; prints "SKIPPED:" when a prerequisite
# is missing.
cmake_minimum_required(VERSION 3.16)

set(SAMPLE ${SOURCE_DIR}/data/sample-carpaint.csv)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

function(fail what)
  message(FATAL_ERROR "${MODE}: ${what}")
endfunction()

function(skip why)
  message("SKIPPED: ${why}")
endfunction()

# run(<prefix> command...): sets <prefix>_rc, _out, _err.
function(run prefix)
  execute_process(COMMAND ${ARGN} WORKING_DIRECTORY ${WORK_DIR}
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(${prefix}_rc "${rc}" PARENT_SCOPE)
  set(${prefix}_out "${out}" PARENT_SCOPE)
  set(${prefix}_err "${err}" PARENT_SCOPE)
endfunction()

function(expect_rc prefix want)
  if(NOT "${${prefix}_rc}" STREQUAL "${want}")
    fail("exit status ${${prefix}_rc}, expected ${want}\nstdout:\n${${prefix}_out}\nstderr:\n${${prefix}_err}")
  endif()
endfunction()

function(expect_match text regex)
  if(NOT "${text}" MATCHES "${regex}")
    fail("expected a match of '${regex}' in:\n${text}")
  endif()
endfunction()

# The sample fitted with glTF model `model`, exported to <model>.gltf; the
# fit's JSON record goes to <model>.json.
function(export_sample model)
  run(r ${BRDFFIT} fit --model ${model} --json --gltf ${model}.gltf ${SAMPLE})
  expect_rc(r 0)
  file(WRITE ${WORK_DIR}/${model}.json "${r_out}")
  if(NOT EXISTS ${WORK_DIR}/${model}.gltf)
    fail("brdffit fit --gltf wrote no ${model}.gltf")
  endif()
endfunction()

if(MODE STREQUAL "gltf_content")
  if(NOT PYTHON)
    skip("python3 not found")
    return()
  endif()
  foreach(model gltf gltf-clearcoat)
    export_sample(${model})
    run(r ${PYTHON} ${TEST_DIR}/check_gltf.py ${WORK_DIR}/${model}.gltf ${WORK_DIR}/${model}.json)
    message("${model}: ${r_out}")
    expect_rc(r 0)
  endforeach()
  # The check does catch a material that is not the fit's.
  file(READ ${WORK_DIR}/gltf.gltf text)
  string(REPLACE "\"metallicFactor\": " "\"metallicFactor\": 0.5, \"x\": " wrong "${text}")
  file(WRITE ${WORK_DIR}/wrong.gltf "${wrong}")
  run(r ${PYTHON} ${TEST_DIR}/check_gltf.py ${WORK_DIR}/wrong.gltf ${WORK_DIR}/gltf.json)
  expect_rc(r 1)
  expect_match("${r_out}" "metallicFactor differs from the fit")
  # Models that are not the glTF BRDF are refused, and nothing is written.
  run(r ${BRDFFIT} fit --model ggx --gltf other.gltf ${SAMPLE})
  expect_rc(r 2)
  expect_match("${r_err}" "^brdffit: --gltf exports the glTF BRDF itself: fit with --model gltf or gltf-clearcoat \\(\"ggx\" is not")
  run(r ${BRDFFIT} fit --gltf other.gltf ${SAMPLE})
  expect_rc(r 2)
  run(r ${BRDFFIT} fit --model gltf --gltf other.gltf ${SAMPLE} ${SAMPLE})
  expect_rc(r 2)
  expect_match("${r_err}" "--gltf with several files needs %s")
  if(EXISTS ${WORK_DIR}/other.gltf)
    fail("a refused --gltf wrote other.gltf")
  endif()
  # An unwritable destination fails the file (exit 1) with its reason.
  run(r ${BRDFFIT} fit --model gltf --gltf no-such-dir/x.gltf ${SAMPLE})
  expect_rc(r 1)
  expect_match("${r_err}" "glTF no-such-dir/x.gltf: cannot create")

elseif(MODE STREQUAL "gltf_validator")
  if(NOT NODE OR NOT NPM)
    skip("node or npm not found: cannot run the Khronos glTF Validator")
    return()
  endif()
  if(NOT EXISTS ${NPM_DIR}/node_modules/gltf-validator/package.json)
    file(MAKE_DIRECTORY ${NPM_DIR})
    execute_process(COMMAND ${NPM} install --no-audit --no-fund --prefix ${NPM_DIR} ${VALIDATOR}
      RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
      skip("npm could not install ${VALIDATOR} into ${NPM_DIR} (exit ${rc}):\n${err}")
      return()
    endif()
  endif()
  set(check ${NODE} ${TEST_DIR}/validate_gltf.js ${NPM_DIR}/node_modules)
  foreach(model gltf gltf-clearcoat)
    export_sample(${model})
    run(r ${check} ${model}.gltf)
    message("${r_out}${r_err}")
    expect_rc(r 0)
    expect_match("${r_out}" "${model}.gltf: 0 errors, 0 warnings")
  endforeach()
  # The validator must catch a broken file: an index accessor whose
  # componentType is not one glTF allows.
  file(READ ${WORK_DIR}/gltf.gltf text)
  string(REPLACE "\"componentType\": 5123" "\"componentType\": 5124" broken "${text}")
  if(broken STREQUAL text)
    fail("gltf.gltf has no index accessor to break")
  endif()
  file(WRITE ${WORK_DIR}/broken.gltf "${broken}")
  run(r ${check} broken.gltf)
  message("${r_out}${r_err}")
  expect_rc(r 1)
  expect_match("${r_out}" "broken.gltf: [1-9][0-9]* errors")

else()
  fail("unknown MODE")
endif()
