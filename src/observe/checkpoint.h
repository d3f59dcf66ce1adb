/* Checkpoints of the observers: each one's accumulators written to / read back from the
 * binary format of core/serial.h. A load goes into an observer allocated from the same
 * configuration and refuses data of another shape (the reader is then marked bad). */
#ifndef HSBD_OBSERVE_CHECKPOINT_H
#define HSBD_OBSERVE_CHECKPOINT_H

#include "core/serial.h"
#include "hsbd/observe.h"

void hsbd_blocks_save(const hsbd_blocks *b, hsbd_writer *w);
int hsbd_blocks_load(hsbd_blocks *b, hsbd_reader *r);
void hsbd_profile_save(const hsbd_profile *p, hsbd_writer *w);
int hsbd_profile_load(hsbd_profile *p, hsbd_reader *r);
void hsbd_msd_save(const hsbd_msd *m, hsbd_writer *w);
int hsbd_msd_load(hsbd_msd *m, hsbd_reader *r);
void hsbd_contacts_save(const hsbd_contacts *c, hsbd_writer *w);
int hsbd_contacts_load(hsbd_contacts *c, hsbd_reader *r);
void hsbd_clusters_save(const hsbd_clusters *c, hsbd_writer *w);
int hsbd_clusters_load(hsbd_clusters *c, hsbd_reader *r);
void hsbd_drift_save(const hsbd_drift *d, hsbd_writer *w);
int hsbd_drift_load(hsbd_drift *d, hsbd_reader *r);
void hsbd_gr_save(const hsbd_gr *g, hsbd_writer *w);
int hsbd_gr_load(hsbd_gr *g, hsbd_reader *r);

#endif
