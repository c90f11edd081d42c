// Package k8s_test renders deploy/k8s with the kustomize API, decodes every object
// strictly with the Kubernetes API types and checks the farm against the compose farm
// (deploy/compose.yaml) and the coordinator's real metrics.
package k8s_test

import (
	"bufio"
	"bytes"
	"context"
	"encoding/json"
	"errors"
	"fmt"
	"io"
	"net/http/httptest"
	"os"
	"regexp"
	"slices"
	"sort"
	"strings"
	"testing"

	appsv1 "k8s.io/api/apps/v1"
	autoscalingv2 "k8s.io/api/autoscaling/v2"
	corev1 "k8s.io/api/core/v1"
	policyv1 "k8s.io/api/policy/v1"
	metav1 "k8s.io/apimachinery/pkg/apis/meta/v1"
	"k8s.io/apimachinery/pkg/labels"
	"k8s.io/apimachinery/pkg/runtime"
	kjson "k8s.io/apimachinery/pkg/runtime/serializer/json"
	utilyaml "k8s.io/apimachinery/pkg/util/yaml"
	"k8s.io/client-go/kubernetes/scheme"
	"sigs.k8s.io/kustomize/api/krusty"
	"sigs.k8s.io/kustomize/kyaml/filesys"
	"sigs.k8s.io/yaml"

	"photonfarm/coordinator/metrics"
	pb "photonfarm/proto/renderfarm/v1"
)

// farm is one rendered kustomization, decoded.
type farm struct {
	objects    []runtime.Object
	workloads  map[string]*corev1.PodTemplateSpec // by Deployment/StatefulSet name
	kinds      map[string]string                  // workload name -> kind
	services   []*corev1.Service
	secrets    map[string]*corev1.Secret
	hpas       []*autoscalingv2.HorizontalPodAutoscaler
	pdbs       []*policyv1.PodDisruptionBudget
	deployment map[string]*appsv1.Deployment
}

// render builds dir with kustomize and decodes each document of its YAML strictly: an
// unknown kind or field is an error.
func render(t *testing.T, dir string) *farm {
	t.Helper()
	resources, err := krusty.MakeKustomizer(krusty.MakeDefaultOptions()).Run(filesys.MakeFsOnDisk(), dir)
	if err != nil {
		t.Fatalf("kustomize build %s: %v", dir, err)
	}
	out, err := resources.AsYaml()
	if err != nil {
		t.Fatal(err)
	}
	strict := kjson.NewSerializerWithOptions(kjson.DefaultMetaFactory, scheme.Scheme, scheme.Scheme,
		kjson.SerializerOptions{Yaml: true, Strict: true})
	f := &farm{workloads: map[string]*corev1.PodTemplateSpec{}, kinds: map[string]string{},
		secrets: map[string]*corev1.Secret{}, deployment: map[string]*appsv1.Deployment{}}
	docs := utilyaml.NewYAMLReader(bufio.NewReader(bytes.NewReader(out)))
	for {
		doc, err := docs.Read()
		if errors.Is(err, io.EOF) {
			break
		}
		if err != nil {
			t.Fatal(err)
		}
		if len(bytes.TrimSpace(doc)) == 0 {
			continue
		}
		obj, gvk, err := strict.Decode(doc, nil, nil)
		if err != nil {
			t.Fatalf("%s: object does not decode strictly: %v\n%s", dir, err, doc)
		}
		f.objects = append(f.objects, obj)
		switch o := obj.(type) {
		case *appsv1.Deployment:
			f.workloads[o.Name], f.kinds[o.Name], f.deployment[o.Name] = &o.Spec.Template, gvk.Kind, o
		case *appsv1.StatefulSet:
			f.workloads[o.Name], f.kinds[o.Name] = &o.Spec.Template, gvk.Kind
		case *corev1.Service:
			f.services = append(f.services, o)
		case *corev1.Secret:
			f.secrets[o.Name] = o
		case *autoscalingv2.HorizontalPodAutoscaler:
			f.hpas = append(f.hpas, o)
		case *policyv1.PodDisruptionBudget:
			f.pdbs = append(f.pdbs, o)
		case *corev1.PersistentVolumeClaim, *corev1.Namespace:
		default:
			t.Errorf("%s: %s %T: the test does not know what to check of it", dir, gvk.Kind, obj)
		}
	}
	if len(f.workloads) == 0 {
		t.Fatalf("%s renders no workload", dir)
	}
	return f
}

// container returns the container named name of the workload named name.
func (f *farm) container(t *testing.T, name string) *corev1.Container {
	t.Helper()
	tpl, ok := f.workloads[name]
	if !ok {
		t.Fatalf("no Deployment or StatefulSet %q", name)
	}
	for i := range tpl.Spec.Containers {
		if tpl.Spec.Containers[i].Name == name {
			return &tpl.Spec.Containers[i]
		}
	}
	t.Fatalf("workload %q has no container %q", name, name)
	return nil
}

var kustomizations = []string{"base", "overlays/example"}

func TestEveryContainerHasResourcesAndProbes(t *testing.T) {
	for _, dir := range kustomizations {
		f := render(t, dir)
		for name, tpl := range f.workloads {
			for _, c := range slices.Concat(tpl.Spec.InitContainers, tpl.Spec.Containers) {
				where := fmt.Sprintf("%s: %s/%s", dir, name, c.Name)
				for _, r := range []corev1.ResourceName{corev1.ResourceCPU, corev1.ResourceMemory} {
					req, lim := c.Resources.Requests[r], c.Resources.Limits[r]
					if req.IsZero() || lim.IsZero() {
						t.Errorf("%s: %s request %v, limit %v: both must be set", where, r, req.String(), lim.String())
					} else if req.Cmp(lim) > 0 {
						t.Errorf("%s: %s request %v exceeds its limit %v", where, r, req.String(), lim.String())
					}
				}
				if c.ReadinessProbe == nil || c.LivenessProbe == nil {
					t.Errorf("%s: readiness %v, liveness %v: both probes are needed", where, c.ReadinessProbe != nil, c.LivenessProbe != nil)
				}
			}
		}
	}
}

// composeFile is what this test reads of deploy/compose.yaml.
type composeFile struct {
	Services map[string]struct {
		Image    string   `json:"image"`
		Command  []string `json:"command"`
		Ports    []string `json:"ports"`
		Networks map[string]struct {
			Aliases []string `json:"aliases"`
		} `json:"networks"`
	} `json:"services"`
}

// composeDefault replaces each ${VAR:-default} (or ${VAR:?message}, which has none) by
// what compose uses when deploy/.env leaves VAR unset.
var composeVar = regexp.MustCompile(`\$\{[A-Z_]+(:-([^}]*)|:\?[^}]*)?\}`)

func composeDefault(s string) string {
	return composeVar.ReplaceAllString(s, "$2")
}

// dockerCmd returns the JSON-array CMD of a Dockerfile (backslash continuations joined).
func dockerCmd(t *testing.T, path string) []string {
	t.Helper()
	b, err := os.ReadFile(path)
	if err != nil {
		t.Fatal(err)
	}
	text := strings.ReplaceAll(string(b), "\\\n", "")
	m := regexp.MustCompile(`(?m)^CMD (\[.*\])\s*$`).FindStringSubmatch(text)
	if m == nil {
		t.Fatalf("%s: no CMD [...]", path)
	}
	var cmd []string
	if err := json.Unmarshal([]byte(m[1]), &cmd); err != nil {
		t.Fatalf("%s: CMD: %v", path, err)
	}
	return cmd
}

// The cluster runs the compose farm's images with the compose farm's flags (at their
// defaults) and exposes the same container ports.
func TestImagesFlagsAndPortsMatchTheComposeFarm(t *testing.T) {
	b, err := os.ReadFile("../compose.yaml")
	if err != nil {
		t.Fatal(err)
	}
	var compose composeFile
	if err := yaml.Unmarshal(b, &compose); err != nil {
		t.Fatalf("deploy/compose.yaml: %v", err)
	}
	if len(compose.Services) == 0 {
		t.Fatal("deploy/compose.yaml has no services")
	}
	for _, dir := range kustomizations {
		f := render(t, dir)
		for service, svc := range compose.Services {
			// Replicas of one role (coordinator-a, coordinator-b) share its name as their
			// network alias: the cluster runs that role as one workload.
			name := service
			if aliases := svc.Networks["default"].Aliases; len(aliases) > 0 {
				name = aliases[0]
			}
			c := f.container(t, name)
			if want := composeDefault(svc.Image); c.Image != want {
				t.Errorf("%s: %s image %q, compose runs %q", dir, name, c.Image, want)
			}
			want := make([]string, len(svc.Command))
			for i, a := range svc.Command {
				want[i] = composeDefault(a)
			}
			if name == "redis" { // compose runs the image's CMD: the AOF settings live there
				want = dockerCmd(t, "../docker/redis.Dockerfile")
			}
			if !slices.Equal(c.Args, want) {
				t.Errorf("%s: %s args\n  %q\ncompose runs\n  %q", dir, name, c.Args, want)
			}
			for _, p := range svc.Ports {
				port := p[strings.LastIndex(p, ":")+1:]
				if !slices.ContainsFunc(c.Ports, func(cp corev1.ContainerPort) bool { return fmt.Sprint(cp.ContainerPort) == port }) {
					t.Errorf("%s: %s does not expose container port %s, which compose publishes", dir, name, port)
				}
			}
		}
		for _, s := range f.services {
			checkService(t, dir, f, s)
		}
	}
}

// checkService fails unless s selects a workload whose container has every target port.
func checkService(t *testing.T, dir string, f *farm, s *corev1.Service) {
	t.Helper()
	sel := labels.SelectorFromSet(s.Spec.Selector)
	for name, tpl := range f.workloads {
		if !sel.Matches(labels.Set(tpl.Labels)) {
			continue
		}
		c := f.container(t, name)
		for _, p := range s.Spec.Ports {
			if !slices.ContainsFunc(c.Ports, func(cp corev1.ContainerPort) bool {
				return cp.Name == p.TargetPort.String() || cp.ContainerPort == p.TargetPort.IntVal
			}) {
				t.Errorf("%s: Service %s port %s targets %s, which container %s does not expose", dir, s.Name, p.Name, p.TargetPort.String(), name)
			}
		}
		return
	}
	t.Errorf("%s: Service %s selects no workload", dir, s.Name)
}

// secretEnv says whether an environment variable holds a secret: a token or a key.
func secretEnv(name string) bool {
	for _, suffix := range []string{"_TOKEN", "_TOKENS", "_KEY", "_KEY_ID"} {
		if strings.HasSuffix(name, suffix) {
			return true
		}
	}
	return false
}

// Tokens and the object store's keys come from Secrets by reference; no manifest carries
// one in a container's env.
func TestTokensAndKeysAreSecretReferences(t *testing.T) {
	for _, dir := range kustomizations {
		f := render(t, dir)
		refs := 0
		for name, tpl := range f.workloads {
			for _, c := range tpl.Spec.Containers {
				for _, e := range c.Env {
					if !secretEnv(e.Name) {
						continue
					}
					ref := e.ValueFrom
					if e.Value != "" || ref == nil || ref.SecretKeyRef == nil {
						t.Errorf("%s: %s/%s: %s is not a secretKeyRef", dir, name, c.Name, e.Name)
						continue
					}
					refs++
					if dir == "base" {
						continue // the base leaves the Secret to an overlay or kubectl
					}
					sec, ok := f.secrets[ref.SecretKeyRef.Name]
					if !ok {
						t.Errorf("%s: %s/%s: %s names Secret %q, which is not rendered", dir, name, c.Name, e.Name, ref.SecretKeyRef.Name)
					} else if _, ok := sec.Data[ref.SecretKeyRef.Key]; !ok {
						t.Errorf("%s: Secret %s has no key %q (%s of %s)", dir, sec.Name, ref.SecretKeyRef.Key, e.Name, name)
					}
				}
			}
		}
		// The coordinator takes both tokens and both keys, the object store both keys, each
		// worker its token.
		if refs < 7 {
			t.Errorf("%s: %d token and key references, want the coordinator's four, the object store's two and the worker's", dir, refs)
		}
		if dir == "base" && len(f.secrets) != 0 {
			t.Errorf("base renders %d Secrets: tokens and keys do not belong in the base", len(f.secrets))
		}
	}
}

// The worker Deployment scales on a queue-depth series that the coordinator really
// exports: the HPA's metric, with its label selector, is looked up in a scrape of the
// coordinator's own metrics handler over a store that counts 7 queued tasks.
func TestWorkersScaleOnTheCoordinatorsQueueDepth(t *testing.T) {
	const queued = 7
	m := metrics.New(func(context.Context) (metrics.Counts, error) {
		return metrics.Counts{Tasks: map[pb.TaskState]int{pb.TaskState_TASK_STATE_QUEUED: queued}}, nil
	})
	rec := httptest.NewRecorder()
	m.Handler().ServeHTTP(rec, httptest.NewRequest("GET", "/metrics", nil))
	exported := rec.Body.String()

	for _, dir := range kustomizations {
		f := render(t, dir)
		if len(f.hpas) != 1 {
			t.Fatalf("%s: %d HorizontalPodAutoscalers, want 1", dir, len(f.hpas))
		}
		h := f.hpas[0]
		ref := h.Spec.ScaleTargetRef
		if ref.Kind != "Deployment" || ref.APIVersion != "apps/v1" || f.deployment[ref.Name] == nil || ref.Name != "worker" {
			t.Errorf("%s: HPA targets %s %s/%s, want the worker Deployment", dir, ref.APIVersion, ref.Kind, ref.Name)
		}
		if len(h.Spec.Metrics) != 1 || h.Spec.Metrics[0].External == nil {
			t.Fatalf("%s: HPA metrics %+v, want one External metric", dir, h.Spec.Metrics)
		}
		ext := h.Spec.Metrics[0].External
		if ext.Metric.Selector == nil || len(ext.Metric.Selector.MatchExpressions) != 0 {
			t.Fatalf("%s: HPA metric selector %v: want matchLabels only", dir, ext.Metric.Selector)
		}
		var pairs []string
		for k, v := range ext.Metric.Selector.MatchLabels {
			pairs = append(pairs, fmt.Sprintf("%s=%q", k, v))
		}
		sort.Strings(pairs)
		series := fmt.Sprintf("%s{%s} %d", ext.Metric.Name, strings.Join(pairs, ","), queued)
		if !strings.Contains(exported, "\n"+series+"\n") {
			t.Errorf("%s: the HPA scales on %q, which the coordinator does not export as the queue depth; it exports:\n%s", dir, series, exported)
		}
		if ext.Target.Type != autoscalingv2.AverageValueMetricType || ext.Target.AverageValue == nil || ext.Target.AverageValue.Sign() <= 0 {
			t.Errorf("%s: HPA target %+v: want a positive AverageValue (queued tasks per worker)", dir, ext.Target)
		}
		if h.Spec.MinReplicas == nil || *h.Spec.MinReplicas < 1 || h.Spec.MaxReplicas < *h.Spec.MinReplicas {
			t.Errorf("%s: HPA replicas %v..%d", dir, h.Spec.MinReplicas, h.Spec.MaxReplicas)
		}
		// A disruption budget covers the workers the HPA scales.
		if f.budget(t, "worker") == nil {
			t.Errorf("%s: no PodDisruptionBudget selects the worker pods", dir)
		}
	}
}

// budget is the PodDisruptionBudget that selects the pods of Deployment name, or nil.
func (f *farm) budget(t *testing.T, name string) *policyv1.PodDisruptionBudget {
	t.Helper()
	d := f.deployment[name]
	if d == nil {
		t.Fatalf("no %s Deployment", name)
	}
	for _, p := range f.pdbs {
		if sel, err := metav1.LabelSelectorAsSelector(p.Spec.Selector); err == nil && sel.Matches(labels.Set(d.Spec.Template.Labels)) {
			return p
		}
	}
	return nil
}

// Coordinator replicas (issue 17): at least two, never all down at once (rolling updates
// that add before they remove, a disruption budget that keeps one), behind a headless
// Service, so that the name resolves to every replica for gRPC's round_robin.
func TestCoordinatorRunsAsReplicasBehindAHeadlessService(t *testing.T) {
	for _, dir := range kustomizations {
		f := render(t, dir)
		d := f.deployment["coordinator"]
		if d == nil {
			t.Fatalf("%s: no coordinator Deployment", dir)
		}
		if d.Spec.Replicas == nil || *d.Spec.Replicas < 2 {
			t.Errorf("%s: coordinator replicas %v, want at least 2", dir, d.Spec.Replicas)
		}
		if ru := d.Spec.Strategy.RollingUpdate; d.Spec.Strategy.Type != appsv1.RollingUpdateDeploymentStrategyType || ru == nil || ru.MaxUnavailable == nil || ru.MaxUnavailable.IntValue() != 0 {
			t.Errorf("%s: coordinator strategy %+v, want a rolling update with maxUnavailable 0", dir, d.Spec.Strategy)
		}
		if p := f.budget(t, "coordinator"); p == nil || p.Spec.MinAvailable == nil || p.Spec.MinAvailable.IntValue() < 1 {
			t.Errorf("%s: no PodDisruptionBudget keeps a coordinator replica up", dir)
		}
		i := slices.IndexFunc(f.services, func(s *corev1.Service) bool { return s.Name == "coordinator" })
		if i < 0 || f.services[i].Spec.ClusterIP != corev1.ClusterIPNone {
			t.Errorf("%s: the coordinator Service is missing or not headless", dir)
		}
	}
}
