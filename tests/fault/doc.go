// Package fault holds the fault-and-load tests of issue 5, run against real processes: a
// `farm coordinator` on a real redis-server, real `farm-worker` processes, SIGKILLed in
// every phase of a job, and a load of many jobs from many clients. See README.md.
package fault
