# prism_add_module(TARGET SOURCE... LIBRARIES LIB...): one of Prism's loadable modules
# (renderer/loadable_module.h), a library opened on first use so that commands which do not
# need it never load its dependencies. It goes where the loader looks, ../lib/prism beside
# every executable of the build and of an installation, and exports only its entry and
# build symbols.
function(prism_add_module target)
  cmake_parse_arguments(PARSE_ARGV 1 MODULE "" "" "LIBRARIES")
  add_library(${target} MODULE ${MODULE_UNPARSED_ARGUMENTS})
  target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}
                                               ${PROJECT_BINARY_DIR}/renderer/generated)
  target_link_libraries(${target} PRIVATE prism_build_flags ${MODULE_LIBRARIES})
  set_target_properties(${target} PROPERTIES
    LIBRARY_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/lib/prism
    CXX_VISIBILITY_PRESET hidden)
  install(TARGETS ${target} LIBRARY DESTINATION lib/prism)
endfunction()
