/* The output series in a checkpoint and their reopening by a restart (output_resume.c). */
#ifndef SPAM_OUTPUT_RESUME_H
#define SPAM_OUTPUT_RESUME_H
#include <spam/output.h>
#include <spam/checkpoint_file.h>

/* The checkpoint's name in the output directory. */
#define SPAM_CHECKPOINT_FILE "checkpoint.h5"

/* Puts the series as they stand (texts, indexes, times, manifest list) into c: on the
 * rank that owns the directory (the texts are read back from its files). */
PetscErrorCode SpamOutputSave(SpamOutput *o, SpamCkFile *c);
/* Takes dir for a run continuing checkpoint c: locks it, removes the files written after
 * the checkpoint, writes back its indexes and opens timeseries.csv and steps.csv holding
 * the checkpoint's rows. (The checkpoint's options were checked: the directory's earlier
 * run is the one being continued, not refused.) */
PetscErrorCode SpamOutputResume(const char *dir, PetscBool hdf5, PetscBool csv, const SpamOutputOptions *opt, const SpamCkFile *c, SpamOutput *o);
/* Checks everything of the series that checkpoint c holds, before the directory is
 * touched: the list of files line by line, the snapshot count (0 to -snapshot_max of opt)
 * against its times (one each with HDF5 snapshots), the step, the times (in order, from 0
 * to the checkpoint's time t), the texts; each refusal is bad input naming the entry. */
PetscErrorCode SpamOutputResumeCheck(const SpamCkFile *c, PetscBool hdf5, const SpamOutputOptions *opt, double t);
/* What every rank keeps of the series (the manifest's list, snapshot and grid counts and
 * times, the step), as checkpoint c holds it: a rank that does not own the directory
 * needs it to name and list the files a restart goes on writing. SpamOutputResume does
 * this for the owner. */
PetscErrorCode SpamOutputResumeLists(const SpamCkFile *c, SpamOutput *o);
#endif
