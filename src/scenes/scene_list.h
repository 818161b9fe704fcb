/* The scenes: the one list. Each row X(Prefix) names the scene's descriptor function
 * SpamScene<Prefix> (defined in its own file, scene_<name>.c), which gives its name, its
 * dimensions, its options (the table -help shows and option_use.c decides relevance from),
 * the size of its params and its hooks. -scene, -help, the relevance of the scene options
 * and the order of the scene names in messages all come from this list (scene_list.c); the
 * first row is the default of -scene. A
 * scene is therefore its file and, here, its row. SPAM_SCENE_LIST_EXTRA appends rows from
 * outside: only the test program that proves this list drives everything
 * (tests/scene_extra/) defines it. */
#ifndef SPAM_SCENE_LIST_H
#define SPAM_SCENE_LIST_H

#ifndef SPAM_SCENE_LIST_EXTRA
#define SPAM_SCENE_LIST_EXTRA(X)
#endif

#define SPAM_SCENE_LIST(X) \
  X(Expansion) \
  X(File) \
  X(Chain) \
  X(Planewave) \
  X(Rotor) \
  X(RotorPair) \
  X(RotorMd) \
  X(Tensile) \
  X(Convection) \
  X(Sod) \
  X(Sedov) \
  X(Gresho) \
  X(TaylorGreen) \
  X(HeatMode) \
  X(Couette) \
  X(Poiseuille) \
  X(Cavity) \
  SPAM_SCENE_LIST_EXTRA(X)
#endif
