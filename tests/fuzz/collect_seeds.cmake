# Seed corpora of the fuzz targets, collected from the cases' dictionary files (cmake -P):
#   cmake -DSOURCE_DIR=<scree> -DOUT=<dir> -P collect_seeds.cmake
# writes OUT/dictionary/<path_with_underscores> (each file as it is) and
# OUT/case/<path_with_underscores> (the file's index as fuzz_case reads it, '0'..'6',
# then the file) for the files named like a case file, from every text file under cases/
# but the documents, data, pictures, scripts and results. Regenerated on every build: nothing is
# committed, and new cases become seeds by themselves.
set(names controlDict gridDict mpmSchemes bodies materialProperties boundaryConditions g)
file(REMOVE_RECURSE "${OUT}/dictionary" "${OUT}/case")
file(MAKE_DIRECTORY "${OUT}/dictionary" "${OUT}/case")
file(GLOB_RECURSE files LIST_DIRECTORIES false RELATIVE "${SOURCE_DIR}" "${SOURCE_DIR}/cases/*")
set(n_dict 0)
set(n_case 0)
foreach(rel ${files})
  file(SIZE "${SOURCE_DIR}/${rel}" size)
  # Dictionary files only: no data, pictures or scripts (by name), nothing large.
  if(size GREATER 65536 OR rel MATCHES "\\.(md|png|py|sh|csv|json|txt|vtp|vtu|pvd|dat|pdf|svg)$"
     OR rel MATCHES "/(VTK|postProcessing|figures|reference)/")
    continue()
  endif()
  file(STRINGS "${SOURCE_DIR}/${rel}" first LIMIT_COUNT 1)
  if(first MATCHES "^#!")  # a script
    continue()
  endif()
  string(REPLACE "/" "_" flat "${rel}")
  configure_file("${SOURCE_DIR}/${rel}" "${OUT}/dictionary/${flat}" COPYONLY)
  math(EXPR n_dict "${n_dict} + 1")
  get_filename_component(name "${rel}" NAME)
  list(FIND names "${name}" index)
  if(index GREATER -1)
    file(READ "${SOURCE_DIR}/${rel}" text)
    file(WRITE "${OUT}/case/${flat}" "${index}${text}")
    math(EXPR n_case "${n_case} + 1")
  endif()
endforeach()
message(STATUS "fuzz seeds: ${n_dict} dictionary files, ${n_case} case files in ${OUT}")
