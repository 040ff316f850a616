# Which optional loaders fuzz_targets.c can call: the MDL and SPR loaders are
# written separately, and until their sources exist those two targets reject
# every input.  Sets EW_FUZZ_DEFS (compile definitions) and EW_FUZZ_TARGETS.
set(EW_FUZZ_DEFS "")
set(EW_FUZZ_TARGETS pak bsp29 bsp2 lmp render lit bspx demo)
if(EXISTS ${CMAKE_SOURCE_DIR}/src/asset/mdl.c AND EXISTS ${CMAKE_SOURCE_DIR}/src/asset/mdl.h)
  list(APPEND EW_FUZZ_DEFS EW_FUZZ_HAVE_MDL=1)
  list(APPEND EW_FUZZ_TARGETS mdl)
endif()
if(EXISTS ${CMAKE_SOURCE_DIR}/src/asset/spr.c AND EXISTS ${CMAKE_SOURCE_DIR}/src/asset/spr.h)
  list(APPEND EW_FUZZ_DEFS EW_FUZZ_HAVE_SPR=1)
  list(APPEND EW_FUZZ_TARGETS spr)
endif()
