/* The test-only scene's row, appended to the scene list (src/scenes/scene_list.h) in the
 * test program built from this folder: its descriptor SpamSceneTestDrift is
 * scene_test_drift.c. */
#define SPAM_SCENE_LIST_EXTRA(X) X(TestDrift)
